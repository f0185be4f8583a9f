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

// Whether `text` ends with `tail` (exactly, case and all).
inline bool ends_with(const std::string& text, const std::string& tail) {
    return text.size() >= tail.size() && text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
}

// `s` with its control characters (newline, tab, carriage return, escape, ... and DEL) written
// as escapes (\n, \t, \r, \xHH), so that a file name cannot split or repaint a one-line message
// or a progress line. Other bytes, UTF-8 included, are kept.
inline std::string printable(const std::string& s) {
    std::string out;
    out.reserve(s.size());
    for (const char ch : s) {
        const unsigned char c = static_cast<unsigned char>(ch);
        if (c >= 0x20 && c != 0x7f) {
            out += ch;
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\t') {
            out += "\\t";
        } else if (c == '\r') {
            out += "\\r";
        } else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", unsigned(c));
            out += hex;
        }
    }
    return out;
}

// ASCII letters lowered (file extensions, keywords); other bytes kept.
inline std::string lowercase(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

}  // namespace npf
