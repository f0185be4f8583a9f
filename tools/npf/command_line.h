// A small, strict command-line parser for the npf subcommands: flags and positional
// arguments, unknown flags are errors, values are checked where they are read.
//
// Conventions every subcommand gets from here (README "Exit status"): "--" ends the options,
// "--version" prints the versions, "--help" the command's help (read_command_line), and usage
// errors are thrown as UsageError, which main reports as one line
// "npf CMD: error: WHAT (see npf CMD --help)" on stderr.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace npf::cli {

struct FlagSpec {
    std::string name;       // "--dirs"
    bool takes_value;
    std::string help;
};

// Exit status of a usage error: a wrong argument count or a missing required flag.
inline constexpr int kUsageStatus = 2;
// Exit status of an option the parser refuses (unknown, value missing, value on a switch): 1,
// as for any other wrong input (a bad value, a bad file), which scripts of every command rely
// on; 2 is for what is missing (README "Exit status").
inline constexpr int kOptionErrorStatus = 1;

class UsageError : public std::runtime_error {
public:
    explicit UsageError(const std::string& what, int status = kUsageStatus)
        : std::runtime_error(what), m_status(status) {}
    int status() const noexcept { return m_status; }

private:
    int m_status;
};

// Thrown by the parser on "--version" (before "--"): main prints the versions and exits 0.
struct VersionRequest {};

class CommandLine {
public:
    // Throws UsageError for unknown flags or missing values, VersionRequest for --version.
    CommandLine(const std::string& command, const std::vector<std::string>& args,
                const std::vector<FlagSpec>& flags);

    bool has(const std::string& flag) const { return m_values.count(flag) > 0; }
    // The last value given for `flag`.
    std::string value(const std::string& flag, const std::string& fallback = "") const;
    const std::vector<std::string>& positional() const { return m_positional; }

    // Typed values (core/number_text.h: one parser and one wording of errors for every command):
    // `fallback` when the flag is not given, else its last value, which must be a whole number
    // in [lo, hi] or a finite number; a bad value throws npf::Error naming the flag (exit 1).
    std::uint64_t whole(const std::string& flag, std::uint64_t lo, std::uint64_t hi, std::uint64_t fallback) const;
    double number(const std::string& flag, double fallback) const;
    // One of a few named values: `fallback` when the flag is not given, else the value paired with
    // its name; another name throws npf::Error(flag, "'NAME' " + refusal), e.g. refusal "is not
    // ggx or beckmann".
    template <class T>
    T choice(const std::string& flag, const std::vector<std::pair<std::string, T>>& choices, T fallback,
             const std::string& refusal) const {
        if (!has(flag)) return fallback;
        const std::string name = value(flag);
        for (const auto& [known, v] : choices) {
            if (known == name) return v;
        }
        refuse_choice(flag, name, refusal);
    }
    // Every flag with its value ("" for switches) in command-line order, repeats included.
    const std::vector<std::pair<std::string, std::string>>& flags_in_order() const { return m_ordered; }

    // Usage errors, checked after --help: between `min` and `max` positional arguments
    // (`what` names them: "one FILE"), and a flag that must be given.
    void expect_positional(std::size_t min, std::size_t max, const std::string& what) const;
    void require(const std::string& flag) const;

private:
    [[noreturn]] static void refuse_choice(const std::string& flag, const std::string& name, const std::string& refusal);

    std::map<std::string, std::string> m_values;
    std::vector<std::pair<std::string, std::string>> m_ordered;
    std::vector<std::string> m_positional;
};

// The flag table for --help, with the options every command takes (--version, --) after it.
std::string usage_lines(const std::vector<FlagSpec>& flags);

// Flags declared as --help lists them, one string each: "NAME  help" for a switch and
// "NAME VALUE  help" for a flag that takes a value, two or more spaces before the help. A table
// reads as the help it prints.
std::vector<FlagSpec> flag_table(std::initializer_list<const char*> lines);

// Thrown by read_command_line on "--help" (before "--"): main prints `text` on stdout and exits 0.
struct HelpRequest {
    std::string text;
};

// A subcommand's arguments, read against its flags and "--help" (added to them) as the
// CommandLine constructor reads them (unknown flags, --version). On --help, throws HelpRequest
// with `help` (usage and description) and the flag table.
CommandLine read_command_line(const std::string& help, const std::vector<FlagSpec>& flags,
                              const std::vector<std::string>& args);

}  // namespace npf::cli
