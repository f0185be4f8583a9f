// Edit recipes and the edit history (issue 7; docs/editing.md): every shipped recipe parses, the
// identity recipe changes nothing, steps run in order, the history goes into the metadata and
// survives the file, and bad recipes fail with the file, the line and the key.
#include "model_equality.h"
#include "npf_test_factors.h"
#include "synthetic_rgl.h"

#include <npf/fit/spectral_compression.h>
#include <npf/core/error.h>
#include <npf/edit/recipe.h>
#include <npf/shading/npf_texture_file.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace {

using npf::NpfModel;
using npf::edit::EditRecipe;

const std::string kEdits = std::string(NPF_SOURCE_DIR) + "/configs/edits";

NpfModel material(bool spectral, bool anisotropic) {
    npf::testing::MicrofacetSpec s;
    s.spectral = spectral;
    s.channels = spectral ? 10 : 3;
    s.alpha_x = 0.2;
    s.alpha_y = anisotropic ? 0.4 : 0.2;
    s.rho_d = 0.05;
    s.rho_s = 0.12;
    s.d_theta = 16;
    s.d_phi = anisotropic ? 32 : 1;
    s.g_theta = 16;
    s.g_phi = anisotropic ? 32 : 1;
    s.f_theta = 16;
    NpfModel m = npf::compress_factors(npf::testing::make_microfacet_factors(s), npf::CompressionOptions());
    m.metadata = {{"description", "test material"}, {"source", "make_microfacet_factors"}};
    return m;
}

std::string error_of(const std::string& yaml) {
    try {
        npf::edit::parse_edit_recipe(yaml, "r.yaml", kEdits);
    } catch (const npf::Error& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(EditRecipe, ShippedRecipesParse) {
    std::size_t count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(kEdits)) {
        if (entry.path().extension() != ".yaml") continue;
        SCOPED_TRACE(entry.path().string());
        EditRecipe r;
        EXPECT_NO_THROW(r = npf::edit::load_edit_recipe(entry.path().string()));
        EXPECT_FALSE(r.steps.empty());
        ++count;
    }
    EXPECT_GE(count, 10u);
}

TEST(EditRecipe, IdentityRecipeChangesNothing) {
    const EditRecipe r = npf::edit::load_edit_recipe(kEdits + "/identity.yaml");
    for (bool spectral : {false, true}) {
        for (bool aniso : {false, true}) {
            const NpfModel m = material(spectral, aniso);
            const npf::edit::EditResult out = npf::edit::apply_edits(m, r.steps, r.options);
            const NpfModel& e = out.model;
            npf::testing::expect_same_factors(e, m);
            EXPECT_EQ(e.D.singular_values, m.D.singular_values);
            EXPECT_EQ(e.d_phi, m.d_phi);
            ASSERT_EQ(out.records.size(), r.steps.size());
            for (const auto& rec : out.records) EXPECT_TRUE(rec.warnings.empty()) << rec.warnings.front();
            EXPECT_EQ(npf::edit::edit_history(e).size(), r.steps.size());
            EXPECT_DOUBLE_EQ(out.output_albedo.max, out.input_albedo.max);
        }
    }
}

TEST(EditRecipe, StepsRunInOrderAndTheHistoryNumbersOn) {
    const EditRecipe r = npf::edit::parse_edit_recipe(
        "description: stretched then rotated\n"
        "steps:\n"
        "  - stretch: {tangent: 2}\n"
        "  - rotate: {degrees: 90}\n"
        "options: {phi_cells: 24}\n",
        "r.yaml", kEdits);
    ASSERT_EQ(r.steps.size(), 2u);
    EXPECT_EQ(r.steps[0].origin, "r.yaml:3");
    EXPECT_EQ(r.options.ndf.phi_cells, 24);
    const NpfModel m = material(false, false);
    const npf::edit::EditResult once = npf::edit::apply_edits(m, r.steps, r.options);
    EXPECT_EQ(once.model.d_phi, 24);
    // Stretch along x, then a quarter turn: the long axis ends along y. In the other order (the
    // turn does nothing to the isotropic input) it stays along x.
    const npf::edit::EditResult reversed = npf::edit::apply_edits(m, {r.steps[1], r.steps[0]}, r.options);
    const npf::Vec3 wi = npf::spherical_direction(0.3f, 0.f), wo_x = npf::spherical_direction(1.0f, npf::kPi);
    const npf::Vec3 wi_y = npf::spherical_direction(0.3f, 0.5f * npf::kPi), wo_y = npf::spherical_direction(1.0f, 1.5f * npf::kPi);
    EXPECT_GT(once.model.eval(0, wi_y, wo_y), 1.5 * once.model.eval(0, wi, wo_x));
    EXPECT_LT(1.5 * reversed.model.eval(0, wi_y, wo_y), reversed.model.eval(0, wi, wo_x));
    const npf::edit::EditResult twice = npf::edit::apply_edits(once.model, {r.steps[0]}, r.options);
    const auto history = npf::edit::edit_history(twice.model);
    ASSERT_EQ(history.size(), 3u);
    EXPECT_EQ(history[0].first, "edit_001");
    EXPECT_EQ(history[2].first, "edit_003");
    EXPECT_NE(history[0].second.find("stretch tangent 2"), std::string::npos) << history[0].second;
    EXPECT_NE(history[1].second.find("rotate"), std::string::npos) << history[1].second;
    std::string description;
    for (const auto& kv : twice.model.metadata) {
        if (kv.first == "description") description = kv.second;
    }
    EXPECT_EQ(description, "stretched then rotated");
    // The source's provenance is kept.
    EXPECT_EQ(twice.model.metadata[1].first, "source");
}

TEST(EditRecipe, HistorySurvivesTheFile) {
    const std::string dir = npf::testing::temporary_folder("edit-recipe");
    const NpfModel m = material(true, true);
    const EditRecipe r = npf::edit::parse_edit_recipe("steps:\n  - diffuse: {spectrum: [[400, 0.2], [700, 0.6]]}\n  - sharpen: 1.5\n",
                                                      "r.yaml", kEdits);
    const npf::edit::EditResult out = npf::edit::apply_edits(m, r.steps, r.options);
    npf::write_npf_texture(out.model, dir + "/edited.exr");
    const NpfModel back = npf::read_npf_texture(dir + "/edited.exr");
    EXPECT_EQ(npf::edit::edit_history(back), npf::edit::edit_history(out.model));
    EXPECT_EQ(back.D.basis, out.model.D.basis);
    EXPECT_EQ(back.rho_d, out.model.rho_d);
}

TEST(EditRecipe, ErrorsNameTheFileLineAndKey) {
    EXPECT_EQ(error_of("steps:\n  - stretch: {tangent: 2, bitangent: x}\n"),
              "r.yaml:2: key 'bitangent': 'x' is not a number");
    EXPECT_EQ(error_of("steps:\n  - stretch: {tangent: 2}\n  - twist: 3\n"),
              "r.yaml:3: key 'twist': unknown step (expected one of: matrix, stretch, rotate, roughness, sharpen, blur, "
              "diffuse, specular, thin_film, compress, limit_albedo)");
    EXPECT_EQ(error_of("steps:\n  - stretch: {tangent: -2}\n"), "r.yaml:2: key 'tangent': must be positive, got -2");
    EXPECT_EQ(error_of("steps: [\n"), "r.yaml:2: not valid YAML: end of sequence flow not found");
    EXPECT_EQ(error_of("stepz: []\n"),
              "r.yaml:1: key 'stepz': unknown key (expected one of: description, steps, options)");
    EXPECT_EQ(error_of("description: x\n"), "r.yaml: missing 'steps' (a list; [] for none)");
    EXPECT_EQ(error_of("steps:\n  - matrix: [[1, 0], [0, 1]]\n"),
              "r.yaml:2: key 'matrix': expected three rows of three numbers (or nine numbers)");
    EXPECT_EQ(error_of("steps:\n  - diffuse: {srgb: [1, 0, 0], from: a.exr}\n"),
              "r.yaml:2: key 'diffuse': give exactly one of from, srgb, linear_srgb, spectrum");
    EXPECT_EQ(error_of("steps:\n  - thin_film: {thickness: 100}\n"), "r.yaml:2: key 'thin_film': missing 'film_ior'");
    EXPECT_EQ(error_of("steps:\n  - thin_film: {thickness: 100, film_ior: 1.3, mode: add}\n"),
              "r.yaml:2: key 'mode': 'add' is not ratio or replace");
    EXPECT_NE(error_of("steps:\n  - thin_film: {thickness: 100, film_ior: 1.3, base: Kryptonite}\n")
                  .find("r.yaml:2: key 'base': "),
              std::string::npos);
    EXPECT_NE(error_of("steps:\n  - diffuse: {spectrum: missing.spd}\n").find("missing.spd"), std::string::npos);
    EXPECT_EQ(error_of("steps:\n  - rotate: 10\noptions: {svd: best}\n"), "r.yaml:3: key 'svd': 'best' is not rank or ratio");
    // A material named by `from` is read when the step runs; the error names the recipe line.
    const EditRecipe r = npf::edit::parse_edit_recipe("steps:\n  - rotate: 5\n  - specular: {from: nothere.exr}\n", "r.yaml", "/nonexistent");
    try {
        npf::edit::apply_edits(material(false, true), r.steps);
        FAIL() << "no error";
    } catch (const npf::Error& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind("r.yaml:3: /nonexistent/nothere.exr", 0), 0u) << what;
    }
    EXPECT_THROW(npf::edit::load_edit_recipe(kEdits + "/no-such-recipe.yaml"), npf::Error);
}

TEST(EditRecipe, RgbMaterialIntoSpectralAndBack) {
    // A diffuse swap across channel kinds through files, as `npf edit` runs it.
    const std::string dir = npf::testing::temporary_folder("edit-recipe-cross");
    npf::write_npf_texture(material(false, false), dir + "/rgb.exr");
    const EditRecipe r = npf::edit::parse_edit_recipe("steps:\n  - diffuse: {from: rgb.exr, scale: 2}\n", "r.yaml", dir);
    const NpfModel spectral = material(true, false);
    const npf::edit::EditResult out = npf::edit::apply_edits(spectral, r.steps);
    // Grey rho_d 0.05 x 2 upsamples to the constant 0.1.
    for (float v : out.model.rho_d) EXPECT_NEAR(v, 0.1, 1e-4);
    EXPECT_EQ(out.model.F, spectral.F);
}

}  // namespace
