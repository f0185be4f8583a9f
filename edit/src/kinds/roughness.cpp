// roughness, sharpen, blur: the roughness scaled in every direction, by a scale or by the factor
// that sharpens or blurs the highlight.
#include "recipe_values.h"

#include "../tables.h"

#include <npf/core/number_text.h>
#include <npf/edit/edit_kinds.h>

namespace npf::edit::kinds {

namespace {

struct RoughnessFactor {
    double factor = 1.0;
};

// `key` is both the recipe key and the flag's name; `inner` the key of its mapping form.
EditKind roughness_kind(const std::string& key, const char* inner, const std::string& help, bool sharpens) {
    return make_edit_kind<RoughnessFactor>({
        key,
        {{"--" + key, help}},
        [key, inner](const YamlContext& cx, const YAML::Node& v) {
            const double f = detail::number_or_mapping(cx, v, key, inner);
            if (!(f > 0.0)) cx.fail(v, key, "must be positive, got " + number_text(f));
            return RoughnessFactor{f};
        },
        [](const std::string& flag, const std::string& text, const GivenFlags&) {
            return RoughnessFactor{flag_positive(flag, text)};
        },
        [key, sharpens](const RoughnessFactor& r) {
            const double scale = sharpens ? 1.0 / r.factor : r.factor;
            return EditStep::ndf(roughness_matrix(scale),
                                 key + " " + number_text(r.factor) + " (roughness x " + number_text(scale) + ")");
        },
    });
}

}  // namespace

EditKind roughness() {
    return roughness_kind("roughness", "scale", "scale the roughness by S in every direction (< 1 sharpens, > 1 blurs)", false);
}

EditKind sharpen() { return roughness_kind("sharpen", "factor", "sharpen the highlight by F (roughness / F)", true); }

EditKind blur() { return roughness_kind("blur", "factor", "blur the highlight by F (roughness x F)", false); }

}  // namespace npf::edit::kinds
