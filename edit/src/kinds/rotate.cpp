// rotate: the NDF (the anisotropy axis) turned about the normal.
#include "recipe_values.h"

#include "../tables.h"

#include <npf/core/number_text.h>
#include <npf/edit/edit_kinds.h>

namespace npf::edit::kinds {

namespace {

struct Rotation {
    double degrees = 0.0;
};

}  // namespace

EditKind rotate() {
    return make_edit_kind<Rotation>({
        "rotate",
        {{"--rotate", "rotate the NDF (anisotropy axis) about the normal by DEG, tangent towards bitangent"}},
        [](const YamlContext& cx, const YAML::Node& v) { return Rotation{detail::number_or_mapping(cx, v, "rotate", "degrees")}; },
        [](const std::string& flag, const std::string& text, const GivenFlags&) { return Rotation{flag_number(flag, text)}; },
        [](const Rotation& r) {
            return EditStep::ndf(rotation_matrix(r.degrees), "rotate the anisotropy axis by " + number_text(r.degrees) + " degrees");
        },
    });
}

}  // namespace npf::edit::kinds
