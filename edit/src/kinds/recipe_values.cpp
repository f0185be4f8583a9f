#include "recipe_values.h"

#include <sstream>
#include <vector>

namespace npf::edit::detail {

double number_or_mapping(const YamlContext& cx, const YAML::Node& node, const std::string& key, const char* inner) {
    if (node.IsScalar()) return cx.number(node, key);
    cx.only(node, key, {inner});
    if (!node[inner]) cx.fail(node, key, std::string("missing '") + inner + "'");
    return cx.number(node[inner], inner);
}

color::SampledSpectrum recipe_spectrum(const YamlContext& cx, const YAML::Node& node, const std::string& key) {
    if (node.IsScalar()) {
        std::istringstream is(node.Scalar());
        double v = 0.0;
        if (is >> v && is.eof()) return color::SampledSpectrum::constant(cx.number(node, key));
        const std::string p = cx.path(node, key);
        return cx.at(node, key, [&] { return color::read_spd(p); });
    }
    if (!node.IsSequence() || node.size() == 0) cx.fail(node, key, "expected a number, a .spd file or [[wavelength_nm, value], ...]");
    return cx.spectrum_rows(node, key);
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
