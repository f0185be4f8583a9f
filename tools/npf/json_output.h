// Small pieces of the subcommands' --json output.
#pragma once

#include <string>

namespace npf::cli {

// A JSON string literal: paths may hold quotes, backslashes or control characters.
std::string json_string(const std::string& text);

}  // namespace npf::cli
