// Values that several edit kinds read from a recipe (edit_kinds.h); errors name the recipe line
// and the key through the YamlContext.
#pragma once

#include <npf/color/spectrum.h>
#include <npf/materials/yaml_context.h>

#include <yaml-cpp/yaml.h>

#include <string>

namespace npf::edit::detail {

// A number, or a mapping with the one key `inner` ("rotate: 30" or "rotate: {degrees: 30}").
double number_or_mapping(const YamlContext& cx, const YAML::Node& node, const std::string& key, const char* inner);

// [r, g, b], each >= 0.
color::Rgb recipe_rgb(const YamlContext& cx, const YAML::Node& node, const std::string& key);

// The optional `scale` of a mapping (>= 0; 1 when left out).
double recipe_scale(const YamlContext& cx, const YAML::Node& map);

}  // namespace npf::edit::detail
