// How one material is processed (private to npf_batch): in the batch's own process, or in a
// worker whose finished files the parent moves into place (so that a worker killed at any point
// publishes nothing). Files are staged under names in the stage folder, reached through its
// descriptor.
#pragma once

#include "batch_folders.h"

#include <npf/batch/config.h>
#include <npf/batch/runner.h>
#include <npf/batch/summary.h>
#include <npf/render/lighting.h>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace npf::batch::detail {

struct MaterialContext {
    const OwnedFolder* stage = nullptr;
    BatchFolders* folders = nullptr;  // in the batch's own process: publishes at once
    bool force = false;
    int shard = 0;
    bool in_worker = false;
    std::uint64_t memory_limit = 0;  // the worker's, for messages
    MaterialHook before_material;    // run_batch_worker's or BatchOptions' (tests)
    std::map<std::string, render::Lighting> environments;  // loaded once per process
    std::vector<std::pair<std::string, std::string>> moves;  // worker: (staged name, final), in order

    std::string staged(const std::string& name) const { return stage->through(name); }
    // Publishes a finished staged file (in a worker: lists it for the parent). Returns where the
    // finished file is to be read from afterwards.
    std::string publish(const std::string& name, const std::string& to, bool render);
};

// The file's size in bytes; 0 when it cannot be examined.
std::uint64_t file_size(const std::string& path);

// "limit 1 GiB" or "no memory limit".
std::string memory_note(std::uint64_t limit);

// A result for the job with what every path knows of it: names, paths, shard.
MaterialResult result_for(const MaterialJob& job, int shard);

// One material: checked against its output's hash, converted, edited, stamped, written, and
// rendered when asked; every problem becomes its failed status and reason.
MaterialResult process_material(const MaterialJob& job, MaterialContext& ctx);

// The parent's check before it starts a worker: whether the output (and its renders) are up to
// date, from the input's bytes and the output's header alone. Nothing: leave it to the worker.
std::optional<MaterialResult> up_to_date_result(const MaterialJob& job, int shard);

}  // namespace npf::batch::detail
