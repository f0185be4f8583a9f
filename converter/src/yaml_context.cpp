#include <npf/converter/yaml_context.h>

#include <npf/core/error.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

namespace npf {

std::string YamlContext::where(const YAML::Node& node) const {
    const YAML::Mark mark = node.Mark();
    return mark.line >= 0 ? source + ":" + std::to_string(mark.line + 1) : source;
}

void YamlContext::fail(const YAML::Node& node, const std::string& key, const std::string& problem) const {
    throw Error(where(node), (key.empty() ? "" : "key '" + key + "': ") + problem);
}

double YamlContext::number(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) fail(node, key, "expected a number");
    double v = 0.0;
    try {
        v = node.as<double>();
    } catch (const YAML::Exception&) {
        fail(node, key, "'" + node.Scalar() + "' is not a number");
    }
    if (!std::isfinite(v)) fail(node, key, "not a finite number");
    return v;
}

double YamlContext::positive(const YAML::Node& node, const std::string& key) const {
    const double v = number(node, key);
    if (!(v > 0.0)) {
        char b[32];
        std::snprintf(b, sizeof b, "%g", v);
        fail(node, key, std::string("must be positive, got ") + b);
    }
    return v;
}

int YamlContext::whole(const YAML::Node& node, const std::string& key, int lo, int hi) const {
    const double v = number(node, key);
    if (v != std::floor(v) || v < lo || v > hi) {
        fail(node, key, "expected a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return int(v);
}

std::string YamlContext::text(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) fail(node, key, "expected text");
    return node.Scalar();
}

std::string YamlContext::path(const YAML::Node& node, const std::string& key) const {
    std::string p = text(node, key);
    if (p.empty()) fail(node, key, "empty path");
    if (p[0] != '/' && !base_dir.empty()) p = base_dir + "/" + p;
    return p;
}

void YamlContext::only(const YAML::Node& map, const std::string& key, const std::vector<std::string>& allowed,
                       const std::vector<std::string>& may_be_empty) const {
    if (!map.IsMap()) fail(map, key, "expected a mapping");
    std::set<std::string> seen;
    for (const auto& kv : map) {
        if (!kv.first.IsScalar()) fail(kv.first, key, "keys must be plain names");
        const std::string k = kv.first.Scalar();
        if (std::find(allowed.begin(), allowed.end(), k) == allowed.end()) {
            std::string names;
            for (const std::string& a : allowed) names += (names.empty() ? "" : ", ") + a;
            const std::string shown = qualify_unknown_keys && !key.empty() ? key + "." + k : k;
            fail(kv.first, shown, "unknown key (expected one of: " + names + ")");
        }
        if (!seen.insert(k).second) fail(kv.first, k, "given twice");
        // An empty value's own position is past it: report the key's line.
        const bool empty_allowed = std::find(may_be_empty.begin(), may_be_empty.end(), k) != may_be_empty.end();
        if (kv.second.IsNull() && !empty_allowed) fail(kv.first, k, "has no value");
    }
}

color::SampledSpectrum YamlContext::spectrum_rows(const YAML::Node& rows, const std::string& key) const {
    std::vector<double> wl, v;
    for (const YAML::Node& row : rows) {
        if (!row.IsSequence() || row.size() != 2) fail(row, key, "each row is [wavelength_nm, value]");
        wl.push_back(number(row[0], key));
        v.push_back(number(row[1], key));
    }
    return at(rows, key, [&] { return color::SampledSpectrum(wl, v); });
}

}  // namespace npf
