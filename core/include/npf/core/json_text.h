// The pieces of JSON text npf writes by hand (command --json output, batch summaries).
#pragma once

#include <string>

namespace npf {

// A JSON string literal: paths and messages may hold quotes, backslashes or control characters.
std::string json_string(const std::string& text);

// %.9g (a float's precision and then some); JSON has no infinity or NaN, so those become null.
std::string json_number(double v);

}  // namespace npf
