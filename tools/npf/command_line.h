// A small, strict command-line parser for the npf subcommands: flags and positional
// arguments, unknown flags are errors, values are checked where they are read.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace npf::cli {

struct FlagSpec {
    std::string name;       // "--dirs"
    bool takes_value;
    std::string help;
};

class CommandLine {
public:
    // Throws npf::Error (source = the subcommand) for unknown flags or missing values.
    CommandLine(const std::string& command, const std::vector<std::string>& args,
                const std::vector<FlagSpec>& flags);

    bool has(const std::string& flag) const { return m_values.count(flag) > 0; }
    std::string value(const std::string& flag, const std::string& fallback = "") const;
    const std::vector<std::string>& positional() const { return m_positional; }

private:
    std::map<std::string, std::string> m_values;
    std::vector<std::string> m_positional;
};

std::string usage_lines(const std::vector<FlagSpec>& flags);

}  // namespace npf::cli
