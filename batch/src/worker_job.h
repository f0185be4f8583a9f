// The job file a worker process reads (private to npf_batch; YAML, its format private to this
// version): the material, the stage folder (with its device and inode, so that the worker uses
// the very folder the batch made) and the names its answers get there.
#pragma once

#include "material_context.h"

#include <npf/batch/config.h>
#include <npf/core/owned_folder.h>

#include <cstdint>
#include <string>

namespace npf::batch::detail {

struct WorkerJob {
    MaterialJob job;
    OwnedFolder stage;
    long parent = 0;  // the batch's process id
    bool force = false;
    int shard = 0;
    std::uint64_t memory_limit = 0;
    std::string result, moves;  // the answers' names in the stage
};

// The job text for `job` as processed in `ctx` (the parent's: stage, force, shard, memory limit).
std::string job_text(const MaterialJob& job, const MaterialContext& ctx, const std::string& result, const std::string& moves);

// The job at `job_path`, read without following a link, and the stage folder it names, which
// must be the one the batch made, holding this very job file. Throws npf::Error otherwise.
WorkerJob read_worker_job(const std::string& job_path);

}  // namespace npf::batch::detail
