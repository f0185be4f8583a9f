// Edit recipes: the YAML file (recipe.h); each step's key names an edit kind (edit_kinds.h),
// which reads its value.
#include <npf/edit/recipe.h>

#include <npf/materials/yaml_context.h>
#include <npf/core/error.h>
#include <npf/core/text_input.h>
#include <npf/core/input_file.h>

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace npf::edit {

namespace {

// Errors name the recipe, the line and the key: "recipe.yaml:7: key 'stretch': ...".
using Context = YamlContext;

EditStep parse_step(const Context& cx, const YAML::Node& node, const EditKinds& kinds) {
    if (!node.IsMap() || node.size() != 1) {
        cx.fail(node, "steps", "each step is a mapping with one key: " + edit_kind_keys(kinds, " or "));
    }
    const auto kv = *node.begin();
    const std::string key = kv.first.Scalar();
    const YAML::Node v = kv.second;
    if (v.IsNull()) cx.fail(kv.first, key, "has no value");
    const EditKind* kind = find_edit_kind(kinds, key);
    if (!kind) cx.fail(kv.first, key, "unknown step (expected one of: " + edit_kind_keys(kinds, ", ") + ")");
    EditStep s = kind->from_recipe(cx, v);
    s.origin = cx.where(kv.first);
    return s;
}

void parse_options(const Context& cx, const YAML::Node& o, EditRecipe& r) {
    cx.only(o, "options", {"phi_cells", "svd", "albedo_tolerance"});
    if (o["phi_cells"]) {
        const double v = cx.number(o["phi_cells"], "phi_cells");
        if (v != std::floor(v) || v < 0 || v > 4096) cx.fail(o["phi_cells"], "phi_cells", "expected a whole number in [0, 4096]");
        r.options.ndf.phi_cells = int(v);
        r.has_phi_cells = true;
    }
    if (o["svd"]) {
        const std::string v = cx.text(o["svd"], "svd");
        if (v == "rank") r.options.ndf.recompress = Recompress::KeepRank;
        else if (v == "ratio") r.options.ndf.recompress = Recompress::KeptRatio;
        else cx.fail(o["svd"], "svd", "'" + v + "' is not rank or ratio");
        r.has_svd = true;
    }
    if (o["albedo_tolerance"]) {
        r.options.albedo_tolerance = cx.number(o["albedo_tolerance"], "albedo_tolerance");
        if (r.options.albedo_tolerance < 0.0) cx.fail(o["albedo_tolerance"], "albedo_tolerance", "must not be negative");
        r.has_albedo_tolerance = true;
    }
}

std::string read_whole(const std::string& path) { return read_text_file(path, "an edit recipe (.yaml)", kRecipeTextBounds); }

}  // namespace

EditRecipe parse_edit_recipe(const std::string& yaml, const std::string& source, const std::string& base_dir,
                             const EditKinds& kinds) {
    Context cx;
    cx.source = source;
    cx.base_dir = base_dir;
    const YAML::Node root = cx.load_mapping(yaml, "an edit recipe is a YAML mapping with a list of steps (see configs/edits/)");
    cx.only(root, "", {"description", "steps", "options"});
    EditRecipe r;
    if (root["description"]) {
        r.options.description = cx.text(root["description"], "description");
        r.has_description = true;
    }
    if (!root["steps"]) throw Error(source, "missing 'steps' (a list; [] for none)");
    const YAML::Node steps = root["steps"];
    if (!steps.IsSequence()) cx.fail(steps, "steps", "expected a list of steps");
    for (const YAML::Node& s : steps) r.steps.push_back(parse_step(cx, s, kinds));
    if (root["options"]) parse_options(cx, root["options"], r);
    return r;
}

EditRecipe parse_edit_recipe(const std::string& yaml, const std::string& source, const std::string& base_dir) {
    return parse_edit_recipe(yaml, source, base_dir, edit_kinds());
}

EditRecipe load_edit_recipe(const std::string& path) {
    const std::string text = read_whole(path);
    std::string dir = std::filesystem::path(path).parent_path().string();
    if (dir.empty()) dir = ".";
    return parse_edit_recipe(text, path, dir);
}

}  // namespace npf::edit
