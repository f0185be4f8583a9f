// The batch's material limits (docs/batch.md "Failure isolation"): memory and wall time of each
// material's worker process, in the words people write them.
#include <npf/batch/config.h>

#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/core/text.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace npf::batch {

namespace {

std::string trimmed(const std::string& v) {
    const std::size_t a = v.find_first_not_of(" \t"), b = v.find_last_not_of(" \t");
    return a == std::string::npos ? std::string() : v.substr(a, b - a + 1);
}

// The number a value starts with, and the rest (trimmed); false when it does not start with one.
bool number_and_unit(const std::string& v, double& number, std::string& unit) {
    const std::string t = trimmed(v);
    if (t.empty() || !(std::isdigit(static_cast<unsigned char>(t[0])) || t[0] == '.')) return false;
    char* end = nullptr;
    number = std::strtod(t.c_str(), &end);
    unit = trimmed(end);
    return end != t.c_str() && std::isfinite(number);
}

}  // namespace

std::uint64_t parse_memory_limit(const std::string& text, const std::string& what) {
    if (lowercase(trimmed(text)) == "none") return 0;
    double n = 0;
    std::string unit;
    const auto fail = [&](const std::string& problem) -> std::uint64_t { throw Error(what, problem + ", got '" + text + "'"); };
    if (!number_and_unit(text, n, unit)) return fail("expects a size such as 8 GiB, 512 MiB or none");
    const std::string u = lowercase(unit);
    static const std::pair<const char*, int> units[] = {{"k", 1}, {"m", 2}, {"g", 3}, {"t", 4}};
    int power = -1;
    for (const auto& [name, p] : units) {
        const std::string b = name;
        if (u == b || u == b + "b" || u == b + "ib") power = p;
    }
    if (power < 0) return fail("needs a unit: K, M, G or T (powers of 1024, as KiB, MiB, GiB, TiB)");
    const double bytes = n * std::pow(1024.0, power);
    if (!(bytes >= double(64u << 20))) return fail("must be at least 64 MiB (or none)");
    if (!(bytes <= std::ldexp(1.0, 62))) return fail("is too large (or use none)");
    return std::uint64_t(bytes);
}

double parse_time_limit(const std::string& text, const std::string& what) {
    if (lowercase(trimmed(text)) == "none") return 0.0;
    double n = 0;
    std::string unit;
    if (!number_and_unit(text, n, unit)) throw Error(what, "expects seconds, or a time such as 90 s, 30 min, 6 h, or none, got '" + text + "'");
    const std::string u = lowercase(unit);
    double scale = 0;
    if (u.empty() || u == "s" || u == "sec" || u == "seconds") scale = 1;
    else if (u == "min" || u == "minutes") scale = 60;
    else if (u == "h" || u == "hours") scale = 3600;
    if (scale == 0) throw Error(what, "unit '" + unit + "' is not one of s, min, h, got '" + text + "'");
    const double seconds = n * scale;
    if (!(seconds > 0.0 && seconds <= 1e9)) throw Error(what, "must be above 0 (or none), got '" + text + "'");
    return seconds;
}

std::string describe_memory(std::uint64_t bytes) {
    if (bytes == 0) return "none";
    static const char* names[] = {"KiB", "MiB", "GiB", "TiB"};
    int i = 3;
    while (i > 0 && double(bytes) < std::ldexp(1.0, 10 * (i + 1))) --i;
    return number_text(double(bytes) / std::ldexp(1.0, 10 * (i + 1)), 4) + " " + names[i];
}

std::string describe_seconds(double seconds) {
    if (seconds <= 0.0) return "none";
    char b[40];
    std::snprintf(b, sizeof b, "%g s", seconds);
    return b;
}

MaterialLimits resolve_limits(const Settings& s) {
    MaterialLimits l;
    if (const auto i = s.find("memory_limit"); i != s.end()) l.memory_bytes = parse_memory_limit(i->second.value, i->second.origin);
    if (const auto i = s.find("time_limit"); i != s.end()) l.seconds = parse_time_limit(i->second.value, i->second.origin);
    return l;
}

}  // namespace npf::batch
