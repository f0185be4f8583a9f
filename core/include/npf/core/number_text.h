// Numbers read from text (command-line flags, configuration values): one parser and one wording
// of their errors for every command and file, so that "--threads 0" reads the same everywhere.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace npf {

// A whole number, decimal digits only (no sign, no spaces), in [lo, hi]; otherwise throws
// npf::Error(what, "needs a whole number in [lo, hi], got 'TEXT'").
std::uint64_t parse_whole_number(const std::string& text, std::uint64_t lo, std::uint64_t hi, const std::string& what);

// A finite number, the whole text in strtod's syntax; otherwise throws
// npf::Error(what, "'TEXT' is not a number").
double parse_finite_number(const std::string& text, const std::string& what);

// Comma-separated finite numbers ("1.5" or "0.2,3.1"), or nothing when any part is not one (the
// text is then something else: a name, a path). Empty parts ("1,,2", "") are not numbers.
std::optional<std::vector<double>> parse_number_list(const std::string& text);

}  // namespace npf
