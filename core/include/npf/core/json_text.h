// The pieces of JSON text npf writes by hand (command --json output, batch summaries).
#pragma once

#include <string>

namespace npf {

// A JSON string literal: paths and messages may hold quotes, backslashes or control characters.
std::string json_string(const std::string& text);

// %.9g (a float's precision and then some) unless told fewer significant digits (timings);
// JSON has no infinity or NaN, so those become null whatever the digits.
std::string json_number(double v, int significant_digits = 9);

}  // namespace npf
