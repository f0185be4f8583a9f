#include "recipe_values.h"

namespace npf::edit::detail {

double number_or_mapping(const YamlContext& cx, const YAML::Node& node, const std::string& key, const char* inner) {
    if (node.IsScalar()) return cx.number(node, key);
    cx.only(node, key, {inner});
    if (!node[inner]) cx.fail(node, key, std::string("missing '") + inner + "'");
    return cx.number(node[inner], inner);
}

color::Rgb recipe_rgb(const YamlContext& cx, const YAML::Node& node, const std::string& key) {
    if (!node.IsSequence() || node.size() != 3) cx.fail(node, key, "expected [r, g, b]");
    color::Rgb c{};
    for (std::size_t i = 0; i < 3; ++i) {
        c[i] = cx.number(node[i], key);
        if (c[i] < 0.0) cx.fail(node[i], key, "colour components are >= 0");
    }
    return c;
}

double recipe_scale(const YamlContext& cx, const YAML::Node& map) {
    if (!map["scale"]) return 1.0;
    const double scale = cx.number(map["scale"], "scale");
    if (scale < 0.0) cx.fail(map["scale"], "scale", "must not be negative");
    return scale;
}

}  // namespace npf::edit::detail
