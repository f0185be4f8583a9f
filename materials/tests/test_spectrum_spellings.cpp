// One way to write a spectrum in YAML (YamlContext::spectrum): material recipes and edit recipes
// accept the same spellings and read each to the same spectrum, so a spectrum copied from one
// kind of recipe into the other means the same thing.
#include "synthetic_rgl.h"

#include <npf/materials/material_recipe.h>
#include <npf/core/error.h>
#include <npf/edit/recipe.h>

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

namespace {

TEST(SpectrumSpellings, MaterialAndEditRecipesReadEverySpellingAlike) {
    const std::string folder = npf::testing::temporary_folder("npf-spellings");
    std::ofstream(folder + "/albedo.spd") << "400 0.2\n550 0.35\n700 0.6\n";
    const std::vector<std::string> spellings = {
        "0.25",
        "[[400, 0.2], [550, 0.35], [700, 0.6]]",
        "{spectrum: [[400, 0.2], [550, 0.35], [700, 0.6]]}",
        "albedo.spd",
        "{file: albedo.spd}",
        "{linear_srgb: [0.2, 0.3, 0.4]}",
        "{srgb: [0.5, 0.6, 0.7]}",
    };
    for (const std::string& s : spellings) {
        SCOPED_TRACE(s);
        const npf::MaterialRecipe material = npf::parse_material_recipe("diffuse: " + s + "\n", "m.yaml", folder);
        const npf::edit::EditRecipe edit =
            npf::edit::parse_edit_recipe("steps:\n  - diffuse: {spectrum: " + s + "}\n", "e.yaml", folder);
        ASSERT_EQ(edit.steps.size(), 1u);
        ASSERT_EQ(edit.steps[0].kind, npf::edit::EditStep::Kind::DiffuseSpectrum);
        const npf::color::SampledSpectrum& a = material.material.diffuse;
        const npf::color::SampledSpectrum& b = edit.steps[0].spectrum;
        EXPECT_FALSE(a.values().empty());
        EXPECT_EQ(a.wavelengths(), b.wavelengths());
        EXPECT_EQ(a.values(), b.values());
    }
    // The rows and the file hold the same samples.
    const auto rows = npf::parse_material_recipe("diffuse: [[400, 0.2], [550, 0.35], [700, 0.6]]\n", "m.yaml", folder);
    const auto file = npf::parse_material_recipe("diffuse: albedo.spd\n", "m.yaml", folder);
    EXPECT_EQ(rows.material.diffuse.values(), file.material.diffuse.values());
}

TEST(SpectrumSpellings, ErrorsNameTheLineAndKeyInBothKinds) {
    const std::string folder = npf::testing::temporary_folder("npf-spellings-errors");
    auto material_error = [&](const std::string& yaml) {
        try {
            npf::parse_material_recipe(yaml, "m.yaml", folder);
        } catch (const npf::Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    auto edit_error = [&](const std::string& yaml) {
        try {
            npf::edit::parse_edit_recipe(yaml, "e.yaml", folder);
        } catch (const npf::Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(material_error("diffuse: missing.spd\n").find("m.yaml:1: key 'diffuse'"), std::string::npos);
    EXPECT_NE(material_error("diffuse: missing.spd\n").find("missing.spd"), std::string::npos);
    EXPECT_NE(edit_error("steps:\n  - diffuse: {spectrum: {srgb: [1, 2]}}\n").find("e.yaml:2: key 'srgb': expected [r, g, b]"),
              std::string::npos);
    EXPECT_NE(edit_error("steps:\n  - diffuse: {spectrum: {file: missing.spd}}\n").find("missing.spd"), std::string::npos);
    EXPECT_NE(material_error("diffuse: [[500, 0.5], [400, 0.5]]\n").find("ascending"), std::string::npos);
}

}  // namespace
