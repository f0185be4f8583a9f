// Reading a batch configuration's values (private to npf_batch): errors name "file:line" and
// the key, unknown keys with their parent ("defaults.presett": settings nest).
#pragma once

#include <npf/batch/config.h>
#include <npf/materials/yaml_context.h>

#include <string>

namespace npf::batch::detail {

struct ConfigReader : YamlContext {
    // One value (not a list or a mapping).
    std::string scalar(const YAML::Node& node, const std::string& key) const;
    // A non-empty path without NUL bytes, made absolute.
    std::string path(const YAML::Node& node, const std::string& key) const;
    // Relative paths are taken from base_dir, the configuration's folder.
    std::string absolute(const std::string& p) const;
    // A scalar or a sequence of scalars joined by commas ("[90, 1, 90, 180]" -> "90,1,90,180").
    std::string list(const YAML::Node& node, const std::string& key) const;
    // A lighting or a list of them ("key-rim", "[studio, maps/dusk.exr]", "studio,directional"):
    // built-in names (render/lighting.h) as they are, map files from the configuration's folder.
    std::string lightings(const YAML::Node& node, const std::string& key) const;
    // Settings of a `defaults` or `materials.NAME` mapping (other keys are left to the caller).
    void settings(const YAML::Node& map, const std::string& prefix, Settings& out) const;
};

}  // namespace npf::batch::detail
