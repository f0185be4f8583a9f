#include "command_line.h"

#include <npf/core/number_text.h>

#include <npf/core/error.h>

#include <cctype>

namespace npf::cli {

CommandLine::CommandLine(const std::string& /*command*/, const std::vector<std::string>& args,
                         const std::vector<FlagSpec>& flags) {
    bool options_ended = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        // "-" alone is a positional (standard input), so is anything after "--" (a file named
        // "-x.bsdf"); "--name=value" is accepted too.
        if (options_ended || a.size() < 2 || a[0] != '-' ||
            (a[1] != '-' && !std::isalpha(static_cast<unsigned char>(a[1])))) {
            m_positional.push_back(a);
            continue;
        }
        if (a == "--") {
            options_ended = true;
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
        if (!spec && a == "--version") throw VersionRequest{};
        if (!spec) throw UsageError("unknown option '" + name + "'", kOptionErrorStatus);
        std::string value;
        if (spec->takes_value) {
            if (has_inline) {
                value = inline_value;
            } else if (i + 1 < args.size()) {
                value = args[++i];
            } else {
                throw UsageError(name + ": needs a value", kOptionErrorStatus);
            }
        } else if (has_inline) {
            throw UsageError(name + ": takes no value", kOptionErrorStatus);
        }
        m_values[name] = value;
        m_ordered.emplace_back(name, value);
    }
}

std::string CommandLine::value(const std::string& flag, const std::string& fallback) const {
    auto it = m_values.find(flag);
    return it == m_values.end() ? fallback : it->second;
}

std::uint64_t CommandLine::whole(const std::string& flag, std::uint64_t lo, std::uint64_t hi, std::uint64_t fallback) const {
    return has(flag) ? parse_whole_number(value(flag), lo, hi, flag) : fallback;
}

double CommandLine::number(const std::string& flag, double fallback) const {
    return has(flag) ? parse_finite_number(value(flag), flag) : fallback;
}

void CommandLine::refuse_choice(const std::string& flag, const std::string& name, const std::string& refusal) {
    throw Error(flag, "'" + name + "' " + refusal);
}

void CommandLine::expect_positional(std::size_t min, std::size_t max, const std::string& what) const {
    const std::size_t n = m_positional.size();
    if (n >= min && n <= max) return;
    if (n == 0) throw UsageError("expects " + what + ", got none");
    throw UsageError("expects " + what + ", got " + std::to_string(n) + " argument" + (n == 1 ? "" : "s"));
}

void CommandLine::require(const std::string& flag) const {
    if (!has(flag)) throw UsageError("missing " + flag + ", which is required");
}

std::string usage_lines(const std::vector<FlagSpec>& flags) {
    std::vector<FlagSpec> all = flags;
    all.push_back({"--version", false, "print the versions of npf and its libraries"});
    all.push_back({"--", false, "end of options: what follows is a file, even '-x.bsdf'"});
    std::string out;
    for (const FlagSpec& f : all) {
        std::string left = "  " + f.name + (f.takes_value ? " VALUE" : "");
        if (left.size() < 24) left.resize(24, ' ');
        out += left + " " + f.help + "\n";
    }
    return out;
}

std::vector<FlagSpec> flag_table(std::initializer_list<const char*> lines) {
    std::vector<FlagSpec> flags;
    for (const std::string line : lines) {
        const std::size_t gap = line.find("  ");
        const std::size_t help = line.find_first_not_of(' ', gap);
        if (gap == std::string::npos || help == std::string::npos) throw std::logic_error("flag_table: '" + line + "'");
        std::string name = line.substr(0, gap);
        const std::string value_mark = " VALUE";
        const bool takes_value = name.size() > value_mark.size() &&
                                 name.compare(name.size() - value_mark.size(), value_mark.size(), value_mark) == 0;
        if (takes_value) name.resize(name.size() - value_mark.size());
        flags.push_back({name, takes_value, line.substr(help)});
    }
    return flags;
}

CommandLine read_command_line(const std::string& help, const std::vector<FlagSpec>& flags,
                              const std::vector<std::string>& args) {
    std::vector<FlagSpec> all = flags;
    all.push_back({"--help", false, "show this help"});
    CommandLine cl("", args, all);
    if (cl.has("--help")) throw HelpRequest{help + usage_lines(all)};
    return cl;
}

}  // namespace npf::cli
