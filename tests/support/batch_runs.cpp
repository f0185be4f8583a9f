#include "batch_runs.h"

namespace npf::testing {

const char* const kBatchTestDefaults = "defaults:\n"
                                       "  preset: preview\n"
                                       "  threads: 1\n"
                                       "  grid: [16, 1, 16, 32]\n"
                                       "  g_grid: [16, 1]\n"
                                       "  error_pairs: 500\n"
                                       "  max_wavelengths: 4\n";

std::string write_batch_config(const std::string& path, const std::string& inputs_dir, const std::string& output_dir,
                               const std::string& extra) {
    write_text(path, "output_dir: " + output_dir + "\ninputs:\n  - " + inputs_dir + "/*.bsdf\n" + kBatchTestDefaults + extra);
    return path;
}

ToolRun batch_run(std::vector<std::string> args) {
    args.insert(args.begin(), "batch");
    return run_tool(args);
}

std::map<std::string, std::string> exr_outputs_of(const std::string& dir) {
    std::map<std::string, std::string> files;
    for (const std::string& name : folder_entries(dir)) {
        if (name.size() > 4 && name.compare(name.size() - 4, 4, ".exr") == 0) files[name] = read_text(dir + "/" + name);
    }
    return files;
}

}  // namespace npf::testing
