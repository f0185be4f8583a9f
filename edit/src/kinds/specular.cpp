// specular: the specular colour rho_s F of another material; D and G stay (colour_edits.h).
#include "recipe_values.h"

#include <npf/edit/edit_kinds.h>

namespace npf::edit::kinds {

namespace {

struct SpecularSource {
    std::string path;
    double scale = 1.0;
    bool keep_brightness = false;
};

SpecularSource read_recipe(const YamlContext& cx, const YAML::Node& v) {
    cx.only(v, "specular", {"from", "scale", "keep_brightness"});
    if (!v["from"]) cx.fail(v, "specular", "missing 'from'");
    SpecularSource s;
    s.scale = detail::recipe_scale(cx, v);
    if (v["keep_brightness"]) {
        const std::string b = cx.text(v["keep_brightness"], "keep_brightness");
        if (b == "true" || b == "yes") s.keep_brightness = true;
        else if (b != "false" && b != "no") cx.fail(v["keep_brightness"], "keep_brightness", "expected true or false");
    }
    s.path = cx.path(v["from"], "from");
    return s;
}

}  // namespace

EditKind specular() {
    return make_edit_kind<SpecularSource>({
        "specular",
        {{"--specular-from", "rho_s F of another NPF material; D and G (the highlight's shape) stay"},
         {"--keep-brightness", "for --specular-from: scale the new rho_s F to the material's own luminance", false, false}},
        read_recipe,
        [](const std::string&, const std::string& text, const GivenFlags& given) {
            return SpecularSource{text, 1.0, given.count("--keep-brightness") > 0};
        },
        [](const SpecularSource& s) { return EditStep::specular_from(s.path, s.scale, s.keep_brightness); },
    });
}

}  // namespace npf::edit::kinds
