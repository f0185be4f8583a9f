#include "config_reader.h"

#include "setting_values.h"

#include <npf/converter/convert_settings_table.h>
#include <npf/core/error.h>
#include <npf/render/lighting.h>

#include <algorithm>
#include <filesystem>

namespace npf::batch::detail {

namespace fs = std::filesystem;

std::string ConfigReader::scalar(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) fail(node, key, "expected a single value");
    return node.Scalar();
}

std::string ConfigReader::path(const YAML::Node& node, const std::string& key) const {
    const std::string p = scalar(node, key);
    if (p.empty()) fail(node, key, "empty path");
    if (p.find('\0') != std::string::npos) fail(node, key, "path holds a NUL byte");
    return absolute(p);
}

std::string ConfigReader::absolute(const std::string& p) const {
    const fs::path q(p);
    return (q.is_absolute() ? q : fs::path(base_dir) / q).lexically_normal().string();
}

std::string ConfigReader::list(const YAML::Node& node, const std::string& key) const {
    if (node.IsScalar()) {
        std::string v = node.Scalar();
        v.erase(std::remove(v.begin(), v.end(), ' '), v.end());
        return v;
    }
    if (!node.IsSequence() || node.size() == 0) fail(node, key, "expected a value or a list of values");
    std::string out;
    for (const YAML::Node& item : node) out += (out.empty() ? "" : ",") + scalar(item, key);
    return out;
}

std::string ConfigReader::lightings(const YAML::Node& node, const std::string& key) const {
    const std::vector<std::string>& names = render::builtin_lighting_names();
    // Items as written (a map's path may hold blanks), trimmed.
    std::vector<std::string> items;
    if (node.IsSequence() && node.size() > 0) {
        for (const YAML::Node& item : node) items.push_back(scalar(item, key));
    } else {
        const std::string given = scalar(node, key);
        for (std::size_t start = 0; start <= given.size();) {
            const std::size_t comma = std::min(given.find(',', start), given.size());
            items.push_back(given.substr(start, comma - start));
            start = comma + 1;
        }
    }
    std::string out;
    for (std::string item : items) {
        const std::size_t a = item.find_first_not_of(" \t"), b = item.find_last_not_of(" \t");
        item = a == std::string::npos ? "" : item.substr(a, b - a + 1);
        if (item.empty()) fail(node, key, "an empty lighting in the list");
        if (item.find('\0') != std::string::npos) fail(node, key, "path holds a NUL byte");
        if (std::find(names.begin(), names.end(), item) == names.end()) item = absolute(item);
        out += (out.empty() ? "" : ",") + item;
    }
    try {
        render::parse_lighting_list(out, key);  // each a name or an existing file, none twice
    } catch (const Error& e) {
        fail(node, key, e.problem());
    }
    return out;
}

void ConfigReader::settings(const YAML::Node& map, const std::string& prefix, Settings& out) const {
    for (const auto& kv : map) {
        const std::string k = kv.first.Scalar();
        if (k == "input" || k == "skip") continue;
        const std::string origin = where(kv.first);
        const std::string full = prefix + k;
        if (k == "edit") {
            const YAML::Node& v = kv.second;
            if (v.IsScalar() && (v.Scalar() == "false" || v.Scalar() == "none")) out[k] = {"", origin};
            else out[k] = {path(v, full), origin};
        } else if (k == "render") {
            const YAML::Node& v = kv.second;
            if (v.IsScalar()) {
                check_value(origin, full, "render", v.Scalar());
                out[k] = {v.Scalar(), origin};
                continue;
            }
            only(v, full, render_keys());
            out[k] = {"true", origin};
            for (const auto& r : v) {
                const std::string rk = r.first.Scalar(), name = "render." + rk;
                const std::string ro = where(r.first);
                if (rk == "env") {
                    out[name] = {lightings(r.second, full + "." + rk), ro};
                } else {
                    const std::string value = scalar(r.second, full + "." + rk);
                    check_value(ro, full + "." + rk, name, value);
                    out[name] = {value, ro};
                }
            }
        } else {
            const ConvertSettingRow* row = find_setting(convert_settings_table(), k);
            const std::string value = row && row->takes_list ? list(kv.second, full) : scalar(kv.second, full);
            check_value(origin, full, k, value);
            out[k] = {value, origin};
        }
    }
}

}  // namespace npf::batch::detail
