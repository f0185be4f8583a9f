// The files one command reads and writes, checked against each other before any work
// (npf::check_distinct_files): an output may not be another output or an input by any name.
#pragma once

#include <npf/core/file_identity.h>

#include <string>
#include <vector>

namespace npf::cli {

class FileUses {
public:
    // `path` is read; a YAML file (a recipe) also reads every file it names.
    FileUses& input(const std::string& path, const std::string& role);
    FileUses& output(const std::string& path, const std::string& role);
    // Throws npf::Error naming the output that would replace another file.
    void check() const { check_distinct_files(m_uses); }

private:
    std::vector<FileUse> m_uses;
};

}  // namespace npf::cli
