// The files and folders a batch run needs, checked before any work: outputs that are no input
// and no other output, and folders that can be written.
#include <npf/batch/runner.h>

#include "validation_renders.h"

#include <npf/core/error.h>
#include <npf/core/file_identity.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include <unistd.h>

namespace npf::batch {

namespace fs = std::filesystem;

void prepare_folder(const std::string& dir, const std::string& what, bool create) {
    std::error_code ec;
    const fs::path d = fs::absolute(fs::path(dir), ec).lexically_normal();
    // The folder itself, or the nearest one above it that exists (where it would be created).
    fs::path existing = d;
    while (!fs::exists(existing, ec) && existing.has_relative_path()) existing = existing.parent_path();
    const std::string how = existing == d ? "" : d.string() + " cannot be created: ";
    if (!fs::is_directory(existing, ec)) throw Error(what, how + existing.string() + " is not a folder");
    if (::access(existing.c_str(), W_OK | X_OK) != 0)
        throw Error(what, how + existing.string() + " is not writable (" + std::strerror(errno) + ")");
    if (create && existing != d) {
        fs::create_directories(d, ec);
        if (ec) throw Error(what, d.string() + " cannot be created: " + ec.message());
    }
}

void check_batch_files(const BatchConfig& config, const std::string& summary_base) {
    // Inputs first: check_distinct_files names the later of two uses, an output.
    std::vector<FileUse> uses;
    if (!config.path.empty()) uses.push_back({config.path, "the configuration", false});
    for (const MaterialJob& m : config.materials) uses.push_back({m.input, "the input of '" + m.name + "'", false});
    for (const MaterialJob& m : config.materials) {
        uses.push_back({m.output, "the output of '" + m.name + "'", true});
        if (!resolve_render_check(m.settings).enabled) continue;
        for (const std::string& l : resolve_render_check(m.settings).lightings)
            for (const char* kind : {"reference", "npf"})
                uses.push_back({detail::render_file(m, l, kind), "a validation render of '" + m.name + "'", true});
    }
    if (!summary_base.empty()) {
        uses.push_back({summary_base + ".json", "the summary", true});
        uses.push_back({summary_base + ".md", "the summary", true});
    }
    check_distinct_files(uses);
}

}  // namespace npf::batch
