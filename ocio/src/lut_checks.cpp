// lut_content_problem: the size claims of the LUT formats OpenColorIO 2.1 reads, checked against
// the bytes the file holds, before OCIO sizes anything by them (sources: OpenColorIO v2.1.2,
// src/OpenColorIO/fileformats/). What OCIO does with a claim:
//  - .cube (Iridas, Resolve), .itx, .vf, .cub (Truelight), .mga/.m3d (Pandora), .look:
//    vector::reserve(3 * n^3) in int arithmetic (overflow past n = 812), before any data is
//    read: an address-space reservation of up to 8 GB, or std::length_error;
//  - .icc/.icm/.pf: tags.resize(count) with the profile's 32-bit tag count, zero-filled: a
//    132-byte file claiming 10^8 tags took 2.3 GB and 4 s (and it is tried on any file whose
//    own reader fails, whatever its extension);
//  - .clf/.ctf: an IndexMap dim or a CTF 1.2 Matrix dim resizes an array before its values are
//    read (dim 10^8: 770 MB for a 300-byte file); LUT1D and LUT3D arrays are capped by OCIO
//    (2^20 entries, 129^3);
//  - .spi1d, .spi3d, .lut (Discreet): sscanf("%s") into 64- and 16-byte stack buffers.
// A real LUT's claims are covered by its own data, so none is refused here.
#include "config_checks.h"

#include <npf/core/number_text.h>
#include <npf/core/text.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace npf::color::detail {

namespace {

// The fewest bytes one value takes: a digit and a separator as text, 8 hex digits in .look.
constexpr double kTextBytesPerValue = 2.0;
constexpr double kLookBytesPerValue = 8.0;
// OCIO's scan buffers: spi1d and spi3d read tokens into char[64], Discreet's depth into char[16].
constexpr std::size_t kSpiTokenBytes = 63;
constexpr std::size_t kDiscreetDepthBytes = 15;

// The integer at the start of `token` as strtol and sscanf("%d") read it (sign, digits).
bool leading_integer(const std::string& token, double& value) {
    std::size_t i = 0;
    const bool negative = !token.empty() && token[0] == '-';
    if (!token.empty() && (token[0] == '-' || token[0] == '+')) ++i;
    if (i >= token.size() || !std::isdigit(static_cast<unsigned char>(token[i]))) return false;
    double v = 0.0;
    for (; i < token.size() && std::isdigit(static_cast<unsigned char>(token[i])); ++i) v = v * 10.0 + (token[i] - '0');
    value = negative ? -v : v;
    return true;
}


// "" when `values` fit in `bytes` at `per_value` bytes each.
std::string claim_problem(const std::string& where, const std::string& what, double values, double bytes,
                          double per_value) {
    if (values < 0.0) return where + " claims a negative size (" + what + ")";
    if (values * per_value <= bytes) return "";
    return where + " claims " + number_text(values) + " values (" + what + ") but the file has " + number_text(bytes) +
           " bytes";
}

std::vector<std::string> tokens_of(const std::string& line) {
    std::vector<std::string> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        const std::size_t b = i;
        while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        if (i > b) out.push_back(line.substr(b, i - b));
    }
    return out;
}

bool starts_with(const std::string& s, const char* head) { return s.compare(0, std::char_traits<char>::length(head), head) == 0; }

// An ICC profile: 'acsp' at byte 36, the tag count (big-endian) at byte 128, 12 bytes a tag.
std::string icc_problem(const std::string& bytes) {
    if (bytes.size() < 132 || bytes.compare(36, 4, "acsp") != 0) return "";
    std::uint32_t count = 0;
    for (int i = 0; i < 4; ++i) count = (count << 8) | static_cast<unsigned char>(bytes[std::size_t(128 + i)]);
    if (double(count) * 12.0 <= double(bytes.size() - 132)) return "";
    return "an ICC profile claiming " + std::to_string(count) + " tags (12 bytes each) in " +
           std::to_string(bytes.size()) + " bytes";
}

// CLF/CTF (XML): every dim="..." (the product of its numbers) and Iridas .look's <size>.
std::string xml_problem(const std::string& bytes) {
    const double size = double(bytes.size());
    for (std::size_t at = bytes.find("dim"); at != std::string::npos; at = bytes.find("dim", at + 3)) {
        std::size_t i = at + 3;
        while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
        if (i >= bytes.size() || bytes[i] != '=') continue;
        ++i;
        while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
        if (i >= bytes.size() || (bytes[i] != '"' && bytes[i] != '\'')) continue;
        const std::size_t close = bytes.find(bytes[i], i + 1);
        if (close == std::string::npos) continue;
        double product = 1.0;
        bool any = false;
        for (const std::string& t : tokens_of(bytes.substr(i + 1, close - i - 1))) {
            double v = 0.0;
            if (!leading_integer(t, v)) continue;
            product *= v;
            any = true;
        }
        const std::string where = "dim=" + bytes.substr(i, std::min<std::size_t>(close - i + 1, 64));
        if (any)
            if (std::string p = claim_problem(where, "the product of its numbers", product, size, kTextBytesPerValue); !p.empty())
                return p;
    }
    for (std::size_t at = bytes.find("<size"); at != std::string::npos; at = bytes.find("<size", at + 5)) {
        std::size_t i = bytes.find('>', at);
        if (i == std::string::npos) break;
        ++i;
        while (i < bytes.size() && (std::isspace(static_cast<unsigned char>(bytes[i])) || bytes[i] == '"')) ++i;
        double n = 0.0;
        if (!leading_integer(bytes.substr(i, 32), n)) continue;
        if (std::string p = claim_problem("<size> " + number_text(n), "3 n^3", 3.0 * n * n * n, size, kLookBytesPerValue); !p.empty())
            return p;
    }
    return "";
}

// The line-based formats: each keyword where any of OCIO's readers takes a size from it.
std::string text_problem(const std::string& bytes) {
    const double size = double(bytes.size());
    // spi3d: a first line "SPILUT"; spi1d: "From" header lines (any file: the header is read up to
    // a "{" line whatever else it holds) and, after a "Version" header, the data lines.
    const bool spi3d = lowercase(bytes.substr(0, 6)) == "spilut";
    bool spi1d_header = true, spi1d_version = false;
    std::size_t line_number = 0;
    for (std::size_t start = 0; start < bytes.size();) {
        std::size_t end = bytes.find('\n', start);
        if (end == std::string::npos) end = bytes.size();
        const std::string line = bytes.substr(start, end - start);
        start = end + 1;
        ++line_number;
        const std::vector<std::string> t = tokens_of(line);
        if (t.empty()) continue;
        const std::string where = "line " + std::to_string(line_number);
        const std::string k0 = lowercase(t[0]);
        const std::string k1 = t.size() > 1 ? lowercase(t[1]) : std::string();
        double a = 0.0, b = 0.0, c = 0.0;
        auto has = [&](std::size_t i, double& v) { return t.size() > i && leading_integer(t[i], v); };
        std::string p;
        if (k0 == "lut_1d_size" && has(1, a)) {
            p = claim_problem(where, "LUT_1D_SIZE " + number_text(a), 3.0 * a, size, kTextBytesPerValue);
        } else if (k0 == "lut_3d_size" && has(1, a)) {
            p = claim_problem(where, "LUT_3D_SIZE " + number_text(a), 3.0 * a * a * a, size, kTextBytesPerValue);
        } else if (k0 == "length" && has(1, a)) {
            p = claim_problem(where, "Length " + number_text(a), a, size, kTextBytesPerValue);
            if (p.empty() && has(2, b)) p = claim_problem(where, "Length " + number_text(b), b, size, kTextBytesPerValue);
        } else if (k0 == "lut:" && has(1, a) && has(2, b)) {
            p = claim_problem(where, "LUT: " + number_text(a) + " " + number_text(b), std::fabs(a) * b, size, kTextBytesPerValue);
            if (p.empty() && t.size() > 3 && t[3].size() > kDiscreetDepthBytes)
                p = where + " has a bit depth of " + std::to_string(t[3].size()) + " characters (OCIO's Discreet reader scans it into " +
                    std::to_string(kDiscreetDepthBytes + 1) + " bytes)";
        } else if (k0 == "grid_size" && has(1, a) && has(2, b) && has(3, c)) {
            p = claim_problem(where, "grid_size", 3.0 * a * b * c, size, kTextBytesPerValue);
        } else if (k0 == "#" && k1 == "width" && has(2, a) && has(3, b) && has(4, c)) {
            p = claim_problem(where, "# width", 3.0 * a * b * c, size, kTextBytesPerValue);
        } else if (k0 == "#" && k1 == "lutlength" && has(2, a)) {
            p = claim_problem(where, "# lutLength", 3.0 * a, size, kTextBytesPerValue);
        } else if (k0 == "in" && has(1, a)) {
            p = claim_problem(where, "in " + number_text(a), 3.0 * a, size, kTextBytesPerValue);
        }
        if (!p.empty()) return p;
        // Tokens of the lines OCIO's spi readers sscanf into char[64].
        const bool scanned = spi3d || (spi1d_header && starts_with(line, "From")) || (!spi1d_header && spi1d_version);
        if (spi1d_header && starts_with(line, "Version")) spi1d_version = true;
        if (spi1d_header && starts_with(line, "{")) spi1d_header = false;
        if (scanned)
            for (const std::string& token : t)
                if (token.size() > kSpiTokenBytes)
                    return where + " has a token of " + std::to_string(token.size()) +
                           " characters (OCIO's spi readers scan tokens into 64 bytes)";
    }
    return "";
}

}  // namespace

std::string lut_content_problem(const std::string& bytes) {
    if (std::string p = icc_problem(bytes); !p.empty()) return p;
    const std::size_t first = bytes.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
    if (first != std::string::npos && bytes[first] == '<') return xml_problem(bytes);
    return text_problem(bytes);
}

}  // namespace npf::color::detail
