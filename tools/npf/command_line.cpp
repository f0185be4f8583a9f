#include "command_line.h"

#include <npf/core/error.h>

namespace npf::cli {

CommandLine::CommandLine(const std::string& command, const std::vector<std::string>& args,
                         const std::vector<FlagSpec>& flags) {
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        // "-" alone is a positional (standard input); "--name=value" is accepted too.
        if (a.size() < 2 || a[0] != '-' || (a[1] != '-' && !std::isalpha(static_cast<unsigned char>(a[1])))) {
            m_positional.push_back(a);
            continue;
        }
        std::string name = a, inline_value;
        bool has_inline = false;
        if (auto eq = a.find('='); eq != std::string::npos) {
            name = a.substr(0, eq);
            inline_value = a.substr(eq + 1);
            has_inline = true;
        }
        const FlagSpec* spec = nullptr;
        for (const FlagSpec& f : flags) {
            if (f.name == name) spec = &f;
        }
        if (!spec) throw Error("", "unknown option '" + name + "' (see npf " + command + " --help)");
        if (spec->takes_value) {
            if (has_inline) {
                m_values[name] = inline_value;
            } else if (i + 1 < args.size()) {
                m_values[name] = args[++i];
            } else {
                throw Error(name, "needs a value");
            }
        } else {
            if (has_inline) throw Error(name, "takes no value");
            m_values[name] = "";
        }
    }
}

std::string CommandLine::value(const std::string& flag, const std::string& fallback) const {
    auto it = m_values.find(flag);
    return it == m_values.end() ? fallback : it->second;
}

std::string usage_lines(const std::vector<FlagSpec>& flags) {
    std::string out;
    for (const FlagSpec& f : flags) {
        std::string left = "  " + f.name + (f.takes_value ? " VALUE" : "");
        if (left.size() < 24) left.resize(24, ' ');
        out += left + " " + f.help + "\n";
    }
    return out;
}

}  // namespace npf::cli
