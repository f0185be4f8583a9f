// stretch: the NDF (the highlight, the roughness) stretched along the tangent and the bitangent.
#include "recipe_values.h"

#include "../tables.h"

#include <npf/core/number_text.h>
#include <npf/edit/edit_kinds.h>

#include <optional>

namespace npf::edit::kinds {

namespace {

// The axes the step names: a recipe names both (1 for one left out), a flag its own.
struct Stretch {
    std::optional<double> tangent, bitangent;
};

Stretch read_recipe(const YamlContext& cx, const YAML::Node& v) {
    cx.only(v, "stretch", {"tangent", "bitangent"});
    if (!v["tangent"] && !v["bitangent"]) cx.fail(v, "stretch", "give tangent, bitangent or both");
    Stretch s;
    s.tangent = v["tangent"] ? cx.positive(v["tangent"], "tangent") : 1.0;
    s.bitangent = v["bitangent"] ? cx.positive(v["bitangent"], "bitangent") : 1.0;
    return s;
}

Stretch read_flag(const std::string& flag, const std::string& text, const GivenFlags&) {
    Stretch s;
    (flag == "--stretch-tangent" ? s.tangent : s.bitangent) = flag_positive(flag, text);
    return s;
}

EditStep build(const Stretch& s) {
    std::string named;
    if (s.tangent) named = "tangent " + number_text(*s.tangent);
    if (s.bitangent) named += (named.empty() ? "" : ", ") + std::string("bitangent ") + number_text(*s.bitangent);
    return EditStep::ndf(stretch_matrix(s.tangent.value_or(1.0), s.bitangent.value_or(1.0)), "stretch " + named);
}

}  // namespace

EditKind stretch() {
    return make_edit_kind<Stretch>({
        "stretch",
        {{"--stretch-tangent", "stretch the NDF (highlight, roughness) along the tangent x by S"},
         {"--stretch-bitangent", "stretch the NDF along the bitangent y by S"}},
        read_recipe,
        read_flag,
        build,
    });
}

}  // namespace npf::edit::kinds
