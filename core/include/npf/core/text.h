// Small text helpers shared by the libraries' error messages.
#pragma once

#include <string>

namespace npf {

// The text up to the first newline. OpenImageIO's geterror() can hold several stacked messages;
// an npf::Error is one line.
inline std::string first_line(const std::string& s) {
    const std::size_t nl = s.find('\n');
    return nl == std::string::npos ? s : s.substr(0, nl);
}

}  // namespace npf
