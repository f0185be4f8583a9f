// Small text helpers shared by the libraries' messages and metadata.
#pragma once

#include <cctype>
#include <cstdio>
#include <string>

namespace npf {

// The text up to the first newline. OpenImageIO's geterror() can hold several stacked messages;
// an npf::Error is one line.
inline std::string first_line(const std::string& s) {
    const std::size_t nl = s.find('\n');
    return nl == std::string::npos ? s : s.substr(0, nl);
}

// A number as "%.6g" writes it: the precision of the metadata and reports that people read
// (factor textures' npf:meta:* values are in this form; changing it changes their bytes).
inline std::string six_digits(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", v);
    return buffer;
}

// Whether `text` ends with `tail` (exactly, case and all).
inline bool ends_with(const std::string& text, const std::string& tail) {
    return text.size() >= tail.size() && text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
}

// ASCII letters lowered (file extensions, keywords); other bytes kept.
inline std::string lowercase(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

}  // namespace npf
