// End-to-end tests of `npf edit`: the identity recipe writes the same factors, flags run in the
// order given after the recipe's steps, `npf info` shows the history, and bad input fails with a
// message naming the problem and leaves no file behind.
#include "model_equality.h"
#include "npf_test_factors.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/fit/spectral_compression.h>
#include <npf/edit/recipe.h>
#include <npf/shading/npf_texture_file.h>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

using npf::NpfModel, npf::testing::contains, npf::testing::describe, npf::testing::folder_entries,
      npf::testing::ToolRun;

const std::string kEdits = std::string(NPF_SOURCE_DIR) + "/configs/edits";

ToolRun edit(std::vector<std::string> args) {
    args.insert(args.begin(), "edit");
    return npf::testing::run_tool(args);
}

// A small anisotropic material in `dir`, returned with its path.
std::string write_material(const std::string& dir, const std::string& name, bool spectral, double rho_s = 0.12) {
    npf::testing::MicrofacetSpec s;
    s.spectral = spectral;
    s.channels = spectral ? 8 : 3;
    s.alpha_x = 0.2;
    s.alpha_y = 0.35;
    s.rho_d = 0.04;
    s.rho_s = rho_s;
    s.set_grid(16, 32, 16, 16, 32);
    NpfModel m = npf::compress_factors(npf::testing::make_microfacet_factors(s), npf::CompressionOptions());
    m.metadata = {{"description", name}};
    const std::string path = dir + "/" + name + ".exr";
    npf::write_npf_texture(m, path);
    return path;
}

TEST(EditCli, IdentityRecipeWritesTheSameFactors) {
    const std::string dir = npf::testing::temporary_folder("edit-cli");
    const std::string in = write_material(dir, "in", true), out = dir + "/out.exr";
    const ToolRun r = edit({in, "-o", out, "--recipe", kEdits + "/identity.yaml"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, "wrote " + out)) << r.out;
    EXPECT_TRUE(contains(r.out, "[5] thin film 0 nm")) << r.out;
    EXPECT_TRUE(r.err.empty()) << r.err;
    const NpfModel a = npf::read_npf_texture(in), b = npf::read_npf_texture(out);
    npf::testing::expect_same_factors(a, b);
    const ToolRun info = npf::testing::run_tool({"info", out});
    ASSERT_EQ(info.status, 0) << describe(info);
    EXPECT_TRUE(contains(info.out, "description: identity edit (no change)")) << info.out;
    EXPECT_TRUE(contains(info.out, "edit_001: matrix [[1, 0, 0], [0, 1, 0], [0, 0, 1]]: ndf transform")) << info.out;
    EXPECT_TRUE(contains(info.out, "edit_005: thin film 0 nm")) << info.out;
}

TEST(EditCli, FlagsRunInOrderAfterTheRecipe) {
    const std::string dir = npf::testing::temporary_folder("edit-cli");
    const std::string in = write_material(dir, "in", false), out = dir + "/out.exr";
    const ToolRun r = edit({in, "-o", out, "--recipe", kEdits + "/sharpen.yaml", "--rotate", "30", "--stretch-tangent=1.5",
                            "--diffuse-srgb", "0.5,0.2,0.1", "--thin-film", "450,1.33", "--film-base", "Al", "--quiet-not-a-flag"});
    EXPECT_EQ(r.status, 1) << describe(r);  // unknown flag
    EXPECT_TRUE(contains(r.err, "unknown option '--quiet-not-a-flag'")) << r.err;
    const ToolRun ok = edit({in, "-o", out, "--recipe", kEdits + "/sharpen.yaml", "--rotate", "30", "--stretch-tangent=1.5",
                             "--diffuse-srgb", "0.5,0.2,0.1", "--thin-film", "450,1.33", "--film-base", "Al"});
    ASSERT_EQ(ok.status, 0) << describe(ok);
    const auto history = npf::edit::edit_history(npf::read_npf_texture(out));
    ASSERT_EQ(history.size(), 5u);
    EXPECT_TRUE(contains(history[0].second, "sharpen 2")) << history[0].second;
    EXPECT_TRUE(contains(history[1].second, "rotate the anisotropy axis by 30 degrees")) << history[1].second;
    EXPECT_TRUE(contains(history[2].second, "stretch tangent 1.5")) << history[2].second;
    EXPECT_TRUE(contains(history[3].second, "diffuse albedo sRGB (0.5,0.2,0.1)")) << history[3].second;
    EXPECT_TRUE(contains(history[4].second, "on base Al")) << history[4].second;
    EXPECT_TRUE(contains(ok.out, "directional albedo: largest")) << ok.out;
}

TEST(EditCli, DiffuseFromAnotherFileAndDryRun) {
    const std::string dir = npf::testing::temporary_folder("edit-cli");
    const std::string in = write_material(dir, "in", true), other = write_material(dir, "other", false);
    const ToolRun r = edit({in, "--dry-run", "--diffuse-from", other, "--specular-from", other});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, "dry run: nothing written")) << r.out;
    EXPECT_EQ(folder_entries(dir), (std::vector<std::string>{"in.exr", "other.exr"}));
}

TEST(EditCli, AlbedoAboveOneIsWarned) {
    const std::string dir = npf::testing::temporary_folder("edit-cli");
    const std::string in = write_material(dir, "in", false), out = dir + "/out.exr";
    const ToolRun r = edit({in, "-o", out, "--diffuse-linear", "1,1,1"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.err, "npf edit: warning: step 1: the directional albedo reaches")) << r.err;
    EXPECT_TRUE(contains(npf::testing::run_tool({"info", out}).out, "WARNING")) << "history keeps the warning";
}

struct BadCase {
    std::vector<std::string> args;
    std::string message;
};

// Each case fails with status 1, names the problem on stderr and leaves no file in `dir` but
// those listed.
void expect_failures(const std::string& dir, const std::vector<BadCase>& cases, const std::vector<std::string>& left) {
    for (const BadCase& c : cases) {
        const ToolRun r = edit(c.args);
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_TRUE(contains(r.err, c.message)) << describe(r);
    }
    EXPECT_EQ(folder_entries(dir), left);
}

TEST(EditCli, ErrorsNameTheProblemAndLeaveNoFile) {
    const std::string dir = npf::testing::temporary_folder("edit-cli");
    const std::string in = write_material(dir, "in", false);
    const std::string out = dir + "/x.exr";
    const std::string bad_recipe = dir + "/bad.yaml";
    ASSERT_TRUE(npf::testing::write_text(bad_recipe, "steps:\n  - rotate: 10\n  - stretch: {tangent: 0}\n"));
    expect_failures(dir,
                    {
                        {{dir + "/missing.exr", "-o", out, "--rotate", "10"}, "missing.exr: cannot open"},
                        {{in, "-o", out, "--recipe", bad_recipe}, "bad.yaml:3: key 'tangent': must be positive"},
                        {{in, "-o", out, "--diffuse-from", dir + "/nothere.exr"}, "--diffuse-from: " + dir + "/nothere.exr"},
                        {{in, "-o", dir + "/no/such/folder/x.exr", "--rotate", "10"}, "no/such/folder"},
                    },
                    {"bad.yaml", "in.exr"});
    EXPECT_EQ(edit({}).status, 2);
    const ToolRun help = edit({"--help"});
    EXPECT_EQ(help.status, 0);
    EXPECT_TRUE(contains(help.out, "--thin-film")) << help.out;
}

// More of the same (each run starts the tool, about 0.25 s).
TEST(SlowEditCli, MoreBadInput) {
    const std::string dir = npf::testing::temporary_folder("edit-cli");
    const std::string in = write_material(dir, "in", false);
    const std::string out = dir + "/x.exr";
    const std::string not_npf = dir + "/plain.yaml";
    ASSERT_TRUE(npf::testing::write_text(not_npf, "steps: []\n"));
    expect_failures(dir,
                    {
                        {{not_npf, "-o", out, "--rotate", "10"}, "plain.yaml"},  // not an NPF file
                        {{in, "-o", out, "--recipe", dir + "/none.yaml"}, "none.yaml"},
                        {{in, "-o", out, "--stretch-tangent", "-1"}, "--stretch-tangent"},
                        {{in, "-o", out, "--matrix", "1,0,0,0,1,0,0,0"}, "--matrix"},
                        {{in, "-o", out, "--diffuse-spectrum", dir + "/nothere.spd"}, "nothere.spd"},
                        {{in, "-o", out, "--diffuse-srgb", "1,0,-1"}, "--diffuse-srgb"},
                        {{in, "-o", out, "--thin-film", "100"}, "--thin-film"},
                        {{in, "-o", out, "--film-base", "Au", "--rotate", "3"}, "--film-base"},
                        {{in, "-o", out, "--thin-film", "100,1.3", "--film-base", "Xx"}, "--film-base"},
                        {{in, "-o", out, "--svd", "some"}, "--svd"},
                        {{in, "-o", out, "--matrix", "1,0,0,0,0,0,0,0,1"}, "singular"},
                        {{in, "-o", out, "--keep-brightness", "--rotate", "2"}, "--keep-brightness"},
                        {{in, "-o", out}, "no edits given"},
                    },
                    {"in.exr", "plain.yaml"});
    EXPECT_EQ(edit({in}).status, 2);  // no -o
}

}  // namespace
