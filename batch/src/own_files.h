// The files a batch writes or owns, which no input may be (private to npf_batch; docs/batch.md
// "Inputs never include the batch's own files"): outputs, its work folder, renders, summaries,
// the configuration.
#pragma once

#include <npf/batch/config.h>

#include <filesystem>
#include <string>

namespace npf::batch::detail {

// `naming` with `name` put in for every {name}.
std::string apply_naming(const std::string& naming, const std::string& name);

// Everything the batch writes or owns, resolved once per configuration.
class OwnFiles {
public:
    explicit OwnFiles(const BatchConfig& c);
    // What `path` is ("an output of the batch (naming ...)", ...), or "" when none of them.
    std::string kind(const std::string& path) const;

private:
    std::filesystem::path m_out;
    std::string m_naming;
    std::filesystem::path m_summary, m_config;
};

}  // namespace npf::batch::detail
