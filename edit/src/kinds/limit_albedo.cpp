// limit_albedo: G lowered where the directional albedo exceeds a cap (albedo_limit.h).
#include "recipe_values.h"

#include "../tables.h"

#include <npf/core/number_text.h>
#include <npf/core/error.h>
#include <npf/edit/edit_kinds.h>

namespace npf::edit::kinds {

namespace {

struct AlbedoCap {
    double cap = 1.0;
};

bool cap_in_range(double cap) { return cap > 0.0 && cap <= 1.0; }

}  // namespace

EditKind limit_albedo() {
    return make_edit_kind<AlbedoCap>({
        "limit_albedo",
        {{"--limit-albedo",
          "cap the directional albedo at CAP (in (0, 1], e.g. 1): G is lowered at the views where the material reflects more "
          "light than that"}},
        [](const YamlContext& cx, const YAML::Node& v) {
            const double cap = detail::number_or_mapping(cx, v, "limit_albedo", "cap");
            if (!cap_in_range(cap)) cx.fail(v, "limit_albedo", "the cap must be in (0, 1], got " + number_text(cap));
            return AlbedoCap{cap};
        },
        [](const std::string& flag, const std::string& text, const GivenFlags&) {
            const double cap = flag_number(flag, text);
            if (!cap_in_range(cap)) throw Error(flag, "the cap must be in (0, 1], got '" + text + "'");
            return AlbedoCap{cap};
        },
        [](const AlbedoCap& c) { return EditStep::limit_albedo(c.cap); },
    });
}

}  // namespace npf::edit::kinds
