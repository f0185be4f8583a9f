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

// A finite decimal number, the whole text: an optional sign, digits with an optional point, an
// optional exponent ("0.25", "-3", "1e-4", ".5"); no blanks, no hex, no "inf" or "nan" (strtod
// alone takes all three). Otherwise throws npf::Error(what, "'TEXT' is not a number").
double parse_finite_number(const std::string& text, const std::string& what);

// The same rule without throwing: nothing when `text` is not such a number.
std::optional<double> finite_number_of(const std::string& text);

// A number as printf's "%.*g" writes it with `significant_digits`: 6 (the default) for the
// metadata and reports people read (factor textures' npf:meta:* values are in this form;
// changing it changes their bytes), 9 for every digit a float holds, 17 for every bit of a
// double (hash texts); "inf", "-inf", "nan" for the rest. The one formatter of numbers.
std::string number_text(double v, int significant_digits = 6);

// The shortest text that reads back as exactly `v` (at most 17 digits; whole numbers without an
// exponent): "0.99", not "0.98999999999999999", and "90", not "9e+01"; for values people set and
// read back, such as defaults in help.
std::string exact_number_text(double v);

// Comma-separated finite numbers ("1.5" or "0.2,3.1"), each as above, or nothing when any part
// is not one (the text is then something else: a name, a path). Empty parts ("1,,2", "") are
// not numbers.
std::optional<std::vector<double>> parse_number_list(const std::string& text);

}  // namespace npf
