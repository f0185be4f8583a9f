#include <npf/core/number_text.h>

#include <npf/core/error.h>

#include <cerrno>
#include <cmath>
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

double parse_finite_number(const std::string& text, const std::string& what) {
    char* end = nullptr;
    const double d = text.empty() ? 0.0 : std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(d)) throw Error(what, "'" + text + "' is not a number");
    return d;
}

std::optional<std::vector<double>> parse_number_list(const std::string& text) {
    std::vector<double> numbers;
    std::size_t begin = 0;
    while (true) {
        const std::size_t comma = text.find(',', begin);
        const std::string part = text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
        char* end = nullptr;
        const double v = part.empty() ? 0.0 : std::strtod(part.c_str(), &end);
        if (part.empty() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
        numbers.push_back(v);
        if (comma == std::string::npos) return numbers;
        begin = comma + 1;
    }
}

}  // namespace npf
