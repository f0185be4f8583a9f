// The parent's side of a worker process (private to npf_batch; docs/batch.md "Failure isolation").
#pragma once

#include "batch_folders.h"

#include <npf/batch/runner.h>
#include <npf/batch/summary.h>

#include <optional>

namespace npf::batch::detail {

// Runs one material in a worker process under its limits and turns however it ended into a
// result: the worker's own, or a failure naming the input and why (signal, limit, exit status).
// Nothing when options.stop ended it: the material was cut short, not done.
std::optional<MaterialResult> run_in_worker(const MaterialJob& job, BatchFolders& folders, const BatchOptions& options);

}  // namespace npf::batch::detail
