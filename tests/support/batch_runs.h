// What the batch tests share: a small configuration over a folder of synthetic RGL files, the
// tool run as `npf batch ...`, and the outputs a run leaves.
#pragma once

#include "run_tool.h"

#include <map>
#include <string>
#include <vector>

namespace npf::testing {

// Tiny, fast settings: each material converts in a fraction of a second.
extern const char* const kBatchTestDefaults;

// Writes a configuration converting `inputs_dir`/*.bsdf into `output_dir` with the defaults
// above, then `extra` (more YAML); returns `path`.
std::string write_batch_config(const std::string& path, const std::string& inputs_dir, const std::string& output_dir,
                               const std::string& extra = "");
// Runs `npf batch args...`.
ToolRun batch_run(std::vector<std::string> args);
// The .exr files in `dir`, name -> bytes.
std::map<std::string, std::string> exr_outputs_of(const std::string& dir);

}  // namespace npf::testing
