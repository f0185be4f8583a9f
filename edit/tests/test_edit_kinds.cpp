// The edit kinds (issue 18; npf/edit/edit_kinds.h): every registered kind is reachable from the
// flags of `npf edit` and from a recipe and builds the same step from the same values; the help
// and the recipe's messages list the registry; a kind added to a registry reaches both readers.
#include "error_of.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/materials/yaml_context.h>
#include <npf/core/error.h>
#include <npf/edit/edit_kinds.h>
#include <npf/edit/recipe.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace {

using npf::testing::error_of;

using npf::edit::EditKind, npf::edit::EditKinds, npf::edit::EditStep, npf::edit::GivenFlags;

std::string exact(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

std::string exact(const std::vector<double>& v) {
    std::string s = "[";
    for (double x : v) s += exact(x) + " ";
    return s + "]";
}

// Everything a step holds but its label and origin, exactly, for comparisons that show the
// difference.
std::string content_of(const EditStep& s) {
    std::string t = "kind " + std::to_string(int(s.kind)) + "; matrix";
    for (double x : s.matrix.m) t += " " + exact(x);
    t += "; path " + s.path + "; scale " + exact(s.scale) + "; keep_brightness " + std::to_string(s.keep_brightness);
    t += "; spectrum " + exact(s.spectrum.wavelengths()) + exact(s.spectrum.values());
    t += "; rgb " + exact(s.rgb[0]) + " " + exact(s.rgb[1]) + " " + exact(s.rgb[2]);
    const npf::edit::ThinFilm& f = s.film;
    t += "; film " + exact(f.thickness_nm) + " eta " + exact(f.film_eta.wavelengths()) + exact(f.film_eta.values()) +
         " base fitted " + std::to_string(f.base.fitted) + " eta " + exact(f.base.eta.values()) + " k " +
         exact(f.base.k.values()) + " '" + f.base.label + "' mode " + std::to_string(int(f.mode));
    t += "; compression " + std::to_string(s.compression.d_rank) + " " + std::to_string(s.compression.g_rank) + " " +
         exact(s.compression.d_ratio) + " " + exact(s.compression.g_ratio);
    return t + "; cap " + exact(s.cap);
}

EditStep recipe_step(const std::string& key, const std::string& value, const std::string& dir,
                     const EditKinds& kinds = npf::edit::edit_kinds()) {
    const npf::edit::EditRecipe r =
        npf::edit::parse_edit_recipe("steps:\n  - " + key + ": " + value + "\n", "r.yaml", dir, kinds);
    EXPECT_EQ(r.steps.size(), 1u);
    return r.steps.empty() ? EditStep{} : r.steps.front();
}

// `flags` as a command line gives them: the step flag first, then its settings.
EditStep flag_step(const std::vector<std::pair<std::string, std::string>>& flags,
                   const EditKinds& kinds = npf::edit::edit_kinds()) {
    GivenFlags given;
    for (const auto& [flag, value] : flags) given[flag] = value;
    npf::edit::check_edit_settings(kinds, given);
    const std::optional<EditStep> s = npf::edit::edit_step_from_flag(kinds, flags.front().first, flags.front().second, given);
    EXPECT_TRUE(s.has_value()) << flags.front().first << " makes no step";
    return s ? *s : EditStep{};
}

struct SameEdit {
    std::string key;
    std::vector<std::pair<std::string, std::string>> flags;  // the step flag and its text, then settings
    std::string recipe_value;
    // Where the two front ends have always named a step differently (a flag's text as typed, a
    // recipe's numbers; the axes a stretch names), the labels differ; the edit does not.
    std::string flag_label, recipe_label;
};

TEST(EditKinds, EveryKindIsReachableFromTheFlagsAndTheRecipeWithTheSameStep) {
    const std::string dir = npf::testing::temporary_folder("edit-kinds");
    ASSERT_TRUE(npf::testing::write_text(dir + "/albedo.spd", "400 0.2\n550 0.5\n700 0.3\n"));
    const std::vector<SameEdit> cases = {
        {"matrix", {{"--matrix", "1,0.3,0,0,1,0,0,0,1"}}, "[[1, 0.3, 0], [0, 1, 0], [0, 0, 1]]",
         "matrix [[1, 0.3, 0], [0, 1, 0], [0, 0, 1]]", "matrix [[1, 0.3, 0], [0, 1, 0], [0, 0, 1]]"},
        {"stretch", {{"--stretch-tangent", "2"}}, "{tangent: 2}", "stretch tangent 2", "stretch tangent 2, bitangent 1"},
        {"stretch", {{"--stretch-bitangent", "0.5"}}, "{bitangent: 0.5}", "stretch bitangent 0.5",
         "stretch tangent 1, bitangent 0.5"},
        {"rotate", {{"--rotate", "30"}}, "{degrees: 30}", "rotate the anisotropy axis by 30 degrees",
         "rotate the anisotropy axis by 30 degrees"},
        {"roughness", {{"--roughness", "0.5"}}, "{scale: 0.5}", "roughness 0.5 (roughness x 0.5)",
         "roughness 0.5 (roughness x 0.5)"},
        {"sharpen", {{"--sharpen", "2"}}, "2", "sharpen 2 (roughness x 0.5)", "sharpen 2 (roughness x 0.5)"},
        {"blur", {{"--blur", "1.5"}}, "{factor: 1.5}", "blur 1.5 (roughness x 1.5)", "blur 1.5 (roughness x 1.5)"},
        {"diffuse", {{"--diffuse-from", dir + "/a.exr"}}, "{from: a.exr}", "diffuse from " + dir + "/a.exr",
         "diffuse from " + dir + "/a.exr"},
        {"diffuse", {{"--diffuse-srgb", "0.5,0.2,0.1"}}, "{srgb: [0.5, 0.2, 0.1]}", "diffuse albedo sRGB (0.5,0.2,0.1)",
         "diffuse albedo sRGB (0.5, 0.2, 0.1)"},
        {"diffuse", {{"--diffuse-linear", "0.1,0.2,0.3"}}, "{linear_srgb: [0.1, 0.2, 0.3]}",
         "diffuse albedo linear sRGB (0.1,0.2,0.3)", "diffuse albedo linear sRGB (0.1, 0.2, 0.3)"},
        {"diffuse", {{"--diffuse-spectrum", dir + "/albedo.spd"}}, "{spectrum: albedo.spd}",
         "diffuse albedo from " + dir + "/albedo.spd", "diffuse albedo from a spectrum"},
        {"specular", {{"--specular-from", dir + "/a.exr"}, {"--keep-brightness", ""}}, "{from: a.exr, keep_brightness: true}",
         "specular from " + dir + "/a.exr, brightness kept", "specular from " + dir + "/a.exr, brightness kept"},
        {"thin_film", {{"--thin-film", "615,1.3"}, {"--film-base", "Au"}, {"--film-mode", "replace"}},
         "{thickness: 615, film_ior: 1.3, base: Au, mode: replace}", "thin film 615 nm, index 1.3",
         "thin film 615 nm, index 1.3"},
        {"compress", {{"--compress-rank", "8,6"}}, "{rank: [8, 6]}", "compress D, G to ranks 8,6",
         "compress D, G to ranks 8, 6"},
        {"compress", {{"--compress-pca", "0.99,0.95"}}, "{pca: [0.99, 0.95]}", "compress D, G to PCA ratios 0.99,0.95",
         "compress D, G to PCA ratios 0.99, 0.95"},
        {"limit_albedo", {{"--limit-albedo", "0.95"}}, "{cap: 0.95}", "limit the directional albedo to 0.95",
         "limit the directional albedo to 0.95"},
    };
    std::set<std::string> keys, flags;
    for (const SameEdit& c : cases) {
        SCOPED_TRACE(c.flags.front().first + " / " + c.key + ": " + c.recipe_value);
        const EditStep from_flag = flag_step(c.flags), from_recipe = recipe_step(c.key, c.recipe_value, dir);
        EXPECT_EQ(content_of(from_flag), content_of(from_recipe));
        EXPECT_EQ(from_flag.label, c.flag_label);
        EXPECT_EQ(from_recipe.label, c.recipe_label);
        EXPECT_EQ(from_flag.origin, c.flags.front().first);
        EXPECT_EQ(from_recipe.origin, "r.yaml:2");
        keys.insert(c.key);
        for (const auto& f : c.flags) flags.insert(f.first);
    }
    // Every kind and every one of its flags is among the cases: a new kind needs its case here.
    for (const EditKind& kind : npf::edit::edit_kinds()) {
        EXPECT_TRUE(keys.count(kind.key)) << "no case for the kind " << kind.key;
        for (const npf::edit::EditFlag& f : kind.flags) EXPECT_TRUE(flags.count(f.name)) << "no case for " << f.name;
    }
}

TEST(EditKinds, TheHelpAndTheRecipeMessagesListTheRegistry) {
    const EditKinds& kinds = npf::edit::edit_kinds();
    const npf::testing::ToolRun help = npf::testing::run_tool({"edit", "--help"});
    ASSERT_EQ(help.status, 0) << npf::testing::describe(help);
    // The help's edit flags are the registry's, in its order, each with its help.
    std::vector<std::string> listed, registered;
    std::set<std::string> known;
    for (const EditKind& kind : kinds) {
        for (const npf::edit::EditFlag& f : kind.flags) {
            registered.push_back(f.name);
            known.insert(f.name);
            bool found = false;
            for (const std::string& line : npf::testing::lines_of(help.out)) {
                if (line.rfind("  " + f.name + " ", 0) == 0) {
                    found = true;
                    EXPECT_EQ(line.substr(line.size() - f.help.size()), f.help) << line;
                    EXPECT_EQ(line.find(" VALUE ") != std::string::npos, f.takes_value) << line;
                }
            }
            EXPECT_TRUE(found) << f.name << " not in the help:\n" << help.out;
        }
    }
    for (const std::string& line : npf::testing::lines_of(help.out)) {
        const std::size_t start = line.find_first_not_of(' ');
        if (start != 2 || line.compare(2, 2, "--") != 0) continue;
        const std::string name = line.substr(2, line.find(' ', 2) - 2);
        if (known.count(name)) listed.push_back(name);
    }
    EXPECT_EQ(listed, registered);
    EXPECT_EQ(npf::edit::edit_kind_keys(kinds, ", "),
              "matrix, stretch, rotate, roughness, sharpen, blur, diffuse, specular, thin_film, compress, limit_albedo");
    EXPECT_EQ(error_of([] { npf::edit::parse_edit_recipe("steps:\n  - twist: 1\n", "r.yaml", "."); }),
              "r.yaml:2: key 'twist': unknown step (expected one of: " + npf::edit::edit_kind_keys(kinds, ", ") + ")");
    EXPECT_EQ(error_of([] { npf::edit::parse_edit_recipe("steps:\n  - 3\n", "r.yaml", "."); }),
              "r.yaml:2: key 'steps': each step is a mapping with one key: " + npf::edit::edit_kind_keys(kinds, " or "));
}

// A kind of the test's own: a grey diffuse albedo.
EditKind grey_kind() {
    return npf::edit::make_edit_kind<double>({
        "grey",
        {{"--grey", "grey diffuse albedo V"}},
        [](const npf::YamlContext& cx, const YAML::Node& v) { return cx.number(v, "grey"); },
        [](const std::string& flag, const std::string& text, const GivenFlags&) { return npf::edit::flag_number(flag, text); },
        [](const double& v) { return EditStep::diffuse_albedo(npf::color::Rgb{v, v, v}, "grey " + exact(v)); },
    });
}

TEST(EditKinds, AKindAddedToTheRegistryReachesTheRecipeAndTheFlags) {
    EditKinds kinds = npf::edit::edit_kinds();
    kinds.push_back(grey_kind());
    const std::string recipe = "steps:\n  - rotate: 10\n  - grey: 0.25\n";
    const npf::edit::EditRecipe r = npf::edit::parse_edit_recipe(recipe, "r.yaml", ".", kinds);
    ASSERT_EQ(r.steps.size(), 2u);
    EXPECT_EQ(r.steps[1].kind, EditStep::Kind::DiffuseRgb);
    EXPECT_EQ(r.steps[1].label, "grey 0.25");
    EXPECT_EQ(r.steps[1].origin, "r.yaml:3");
    const EditStep s = flag_step({{"--grey", "0.25"}}, kinds);
    EXPECT_EQ(content_of(s), content_of(r.steps[1]));
    EXPECT_EQ(s.label, "grey 0.25");
    EXPECT_EQ(error_of([&] { npf::edit::parse_edit_recipe("steps:\n  - twirl: 1\n", "r.yaml", ".", kinds); }),
              "r.yaml:2: key 'twirl': unknown step (expected one of: matrix, stretch, rotate, roughness, sharpen, blur, "
              "diffuse, specular, thin_film, compress, limit_albedo, grey)");
    // The library's own registry does not know it.
    EXPECT_NE(error_of([&] { npf::edit::parse_edit_recipe(recipe, "r.yaml", "."); }).find("key 'grey': unknown step"),
              std::string::npos);
    EXPECT_FALSE(npf::edit::edit_step_from_flag(npf::edit::edit_kinds(), "--grey", "0.25", {}).has_value());
}

TEST(EditKinds, FlagErrorsNameTheFlag) {
    const EditKinds& kinds = npf::edit::edit_kinds();
    const auto flag_error = [&](const GivenFlags& given, const std::string& flag) {
        return error_of([&] {
            npf::edit::check_edit_settings(kinds, given);
            npf::edit::edit_step_from_flag(kinds, flag, given.count(flag) ? given.at(flag) : "", given);
        });
    };
    EXPECT_EQ(flag_error({{"--film-base", "Au"}, {"--rotate", "3"}}, "--rotate"),
              "--film-base: applies to --thin-film, which is not given");
    EXPECT_EQ(flag_error({{"--film-mode", "ratio"}}, "--rotate"), "--film-mode: applies to --thin-film, which is not given");
    EXPECT_EQ(flag_error({{"--keep-brightness", ""}}, "--rotate"),
              "--keep-brightness: applies to --specular-from, which is not given");
    // A setting's value fails before the steps, and before its missing step is noticed.
    EXPECT_EQ(flag_error({{"--film-mode", "x"}}, "--rotate"), "--film-mode: 'x' is not ratio or replace");
    EXPECT_EQ(flag_error({{"--thin-film", "100"}}, "--thin-film"), "--thin-film: expects 2 comma-separated numbers, got '100'");
    EXPECT_EQ(flag_error({{"--stretch-tangent", "-1"}}, "--stretch-tangent"), "--stretch-tangent: must be positive, got '-1'");
    EXPECT_EQ(flag_error({{"--diffuse-srgb", "1,0,-1"}}, "--diffuse-srgb"),
              "--diffuse-srgb: colour components are >= 0, got '1,0,-1'");
    EXPECT_EQ(flag_error({{"--compress-rank", "1.5,2"}}, "--compress-rank"), "--compress-rank: ranks are whole numbers >= 1");
    EXPECT_EQ(flag_error({{"--limit-albedo", "2"}}, "--limit-albedo"), "--limit-albedo: the cap must be in (0, 1], got '2'");
    // Settings make no step of their own.
    EXPECT_FALSE(npf::edit::edit_step_from_flag(kinds, "--film-base", "Au", {{"--thin-film", "1,1.3"}}).has_value());
    EXPECT_FALSE(npf::edit::edit_step_from_flag(kinds, "-o", "x.exr", {}).has_value());
}

}  // namespace
