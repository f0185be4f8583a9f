// The row makers and text helpers every setting declaration shares.
#include "setting_rows.h"

#include <npf/core/number_text.h>

namespace npf::settings_rows {

std::string g17(double v) { return number_text(v, 17); }

std::vector<std::string> split(const std::string& v, char separator) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t at = v.find(separator, start);
        out.push_back(v.substr(start, at == std::string::npos ? std::string::npos : at - start));
        if (at == std::string::npos) return out;
        start = at + 1;
    }
}

std::string join(const std::vector<std::string>& parts, const char* separator) {
    std::string out;
    for (const std::string& p : parts) out += (out.empty() ? "" : separator) + p;
    return out;
}

std::string range_text(const Range& r) {
    return std::string(r.low_open ? "(" : "[") + g17(r.low) + ", " + g17(r.high) + "]";
}

std::string grid_text(const DetailGrid& g, char separator) {
    const std::string sep(1, separator);
    return std::to_string(g.theta_h) + sep + std::to_string(g.theta_d) + sep + std::to_string(g.phi_d);
}

namespace {

Row row_of(std::string key, SettingKind kind, std::string help) {
    Row r;
    r.key = std::move(key);
    r.kind = kind;
    r.help = std::move(help);
    return r;
}

}  // namespace

Row whole(std::string key, std::vector<Range> ranges, std::string help) {
    Row r = row_of(std::move(key), SettingKind::Whole, std::move(help));
    r.least_parts = r.most_parts = ranges.size();
    r.ranges = std::move(ranges);
    return r;
}

Row number(std::string key, std::size_t least_parts, std::size_t most_parts, std::vector<Range> ranges, std::string range_problem,
           std::string help) {
    Row r = row_of(std::move(key), SettingKind::Number, std::move(help));
    r.least_parts = least_parts;
    r.most_parts = most_parts;
    r.ranges = std::move(ranges);
    r.range_problem = std::move(range_problem);
    return r;
}

Row choice(std::string key, std::vector<std::string> choices, std::string help) {
    Row r = row_of(std::move(key), SettingKind::Choice, std::move(help));
    r.choices = std::move(choices);
    return r;
}

Row text(std::string key, std::function<void(const std::string&, const std::string&)> check, std::string help) {
    Row r = row_of(std::move(key), SettingKind::Text, std::move(help));
    r.check = std::move(check);
    return r;
}

Row switched(std::string key, std::string help) { return row_of(std::move(key), SettingKind::Switch, std::move(help)); }

Row always_hashed(Row r) {
    r.hash = SettingHash::Always;
    return r;
}

Row preset_only(Row r) {
    r.preset_only = true;
    return r;
}

}  // namespace npf::settings_rows
