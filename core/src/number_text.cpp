#include <npf/core/number_text.h>

#include <npf/core/error.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace npf {

std::uint64_t parse_whole_number(const std::string& text, std::uint64_t lo, std::uint64_t hi, const std::string& what) {
    const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
    errno = 0;
    const unsigned long long n = digits ? std::strtoull(text.c_str(), nullptr, 10) : 0;
    if (!digits || errno == ERANGE || n < lo || n > hi) {
        throw Error(what, "needs a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" + text + "'");
    }
    return n;
}

namespace {

// [+-] digits [. digits] [(e|E) [+-] digits], at least one digit before the exponent.
bool plain_decimal(const std::string& t) {
    std::size_t i = 0;
    const auto digits = [&] {
        const std::size_t from = i;
        while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i;
        return i - from;
    };
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    std::size_t mantissa = digits();
    if (i < t.size() && t[i] == '.') {
        ++i;
        mantissa += digits();
    }
    if (mantissa == 0) return false;
    if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
        ++i;
        if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
        if (digits() == 0) return false;
    }
    return i == t.size();
}

}  // namespace

std::optional<double> finite_number_of(const std::string& text) {
    if (!plain_decimal(text)) return std::nullopt;
    const double d = std::strtod(text.c_str(), nullptr);
    if (!std::isfinite(d)) return std::nullopt;  // out of double's range ("1e999")
    return d;
}

double parse_finite_number(const std::string& text, const std::string& what) {
    const std::optional<double> d = finite_number_of(text);
    if (!d) throw Error(what, "'" + text + "' is not a number");
    return *d;
}

std::string number_text(double v, int significant_digits) {
    char b[48];
    std::snprintf(b, sizeof b, "%.*g", significant_digits, v);
    return b;
}

std::string exact_number_text(double v) {
    if (std::isfinite(v) && v == std::trunc(v) && std::fabs(v) < 1e15) {  // "90", not "9e+01"
        char b[32];
        std::snprintf(b, sizeof b, "%.0f", v);
        return b;
    }
    for (int digits = 1; digits < 17; ++digits) {
        const std::string text = number_text(v, digits);
        if (std::strtod(text.c_str(), nullptr) == v) return text;
    }
    return number_text(v, 17);
}

std::optional<std::vector<double>> parse_number_list(const std::string& text) {
    std::vector<double> numbers;
    std::size_t begin = 0;
    while (true) {
        const std::size_t comma = text.find(',', begin);
        const std::string part = text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
        const std::optional<double> v = finite_number_of(part);
        if (!v) return std::nullopt;
        numbers.push_back(*v);
        if (comma == std::string::npos) return numbers;
        begin = comma + 1;
    }
}

}  // namespace npf
