#include <npf/materials/yaml_context.h>

#include <npf/core/error.h>

#include <npf/core/text.h>
#include <npf/core/text_input.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

namespace npf {

YAML::Node YamlContext::load_mapping(const std::string& yaml, const std::string& not_a_mapping) const {
    YAML::Node root;
    try {
        root = YAML::Load(yaml);
    } catch (const YAML::Exception& e) {
        throw Error(e.mark.line >= 0 ? source + ":" + std::to_string(e.mark.line + 1) : source, "not valid YAML: " + e.msg);
    }
    if (!root.IsMap()) throw Error(source, not_a_mapping);
    return root;
}

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

namespace {

bool names_a_spectrum_file(const std::string& text) {
    return ends_with(lowercase(text), ".spd") || text.find('/') != std::string::npos;
}

}  // namespace

color::SampledSpectrum YamlContext::spectrum(const YAML::Node& node, const std::string& key) const {
    if (node.IsScalar()) {
        if (names_a_spectrum_file(node.Scalar())) {
            const std::string p = path(node, key);
            return at(node, key, [&] { return color::read_spd(p); });
        }
        return color::SampledSpectrum::constant(number(node, key));
    }
    if (node.IsSequence()) {
        if (node.size() > 0 && node[0].IsSequence()) return spectrum_rows(node, key);
        fail(node, key, "expected a mapping (srgb, linear_srgb, spectrum or file), a number, a .spd file or "
                        "[[wavelength_nm, value], ...]");
    }
    only(node, key, {"srgb", "linear_srgb", "spectrum", "file"});
    if (node.size() != 1) fail(node, key, "give exactly one of srgb, linear_srgb, spectrum, file");
    const auto kv = *node.begin();
    const std::string kind = kv.first.Scalar();
    const YAML::Node value = kv.second;
    if (kind == "srgb" || kind == "linear_srgb") {
        if (!value.IsSequence() || value.size() != 3) fail(value, kind, "expected [r, g, b]");
        double c[3];
        for (int i = 0; i < 3; ++i) c[i] = number(value[i], kind);
        if (kind == "srgb") return color::srgb_to_spectrum(c[0], c[1], c[2]);
        return color::linear_srgb_to_spectrum({c[0], c[1], c[2]});
    }
    if (kind == "file") {
        const std::string p = path(value, kind);
        return at(value, kind, [&] { return color::read_spd(p); });
    }
    if (!value.IsSequence() || value.size() == 0) fail(value, kind, "expected [[wavelength_nm, value], ...]");
    return spectrum_rows(value, kind);
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

std::vector<std::pair<std::string, std::string>> files_named_in_yaml(const std::string& path) {
    namespace fs = std::filesystem;
    std::vector<YAML::Node> todo;
    try {
        todo.push_back(YAML::Load(read_text_file(path, "a YAML file", kRecipeTextBounds)));
    } catch (const std::exception&) {
        return {};
    }
    const fs::path dir = fs::path(path).parent_path();
    std::map<std::string, std::string> files;
    // Aliases share nodes, so a small document can expand to billions of visits ("billion
    // laughs"): a recipe names a few files, and the walk stops after 2^16 nodes.
    for (std::size_t visited = 0; !todo.empty() && visited < (std::size_t(1) << 16); ++visited) {
        const YAML::Node n = todo.back();
        todo.pop_back();
        if (n.IsScalar()) {
            const std::string v = n.Scalar();
            if (v.empty() || v.size() > 4096 || v.find('\0') != std::string::npos) continue;
            const fs::path p = fs::path(v).is_absolute() ? fs::path(v) : dir / v;
            std::error_code ec;
            if (fs::is_regular_file(p, ec)) files[v] = p.string();
        } else if (n.IsSequence()) {
            for (const YAML::Node& c : n) todo.push_back(c);
        } else if (n.IsMap()) {
            for (const auto& kv : n) todo.push_back(kv.second);
        }
    }
    return {files.begin(), files.end()};
}

}  // namespace npf
