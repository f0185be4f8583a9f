// The detail layer's peak and energy (issue 34, item 2): the half-angle measure keeps a narrow
// peak's height that the solid-angle measure gives away, and the clamp passes make the stored
// layer (clamp max(0, NPF + r) included) hold the source's albedo.
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace {

using npf::testing::describe;
using npf::testing::run_tool;

// The value of metadata line `key` of `npf info FILE`.
double metadata_number(const std::string& file, const std::string& key) {
    const npf::testing::ToolRun info = run_tool({"info", file});
    const std::size_t at = info.out.find("\n" + key + ": ");
    if (at == std::string::npos) ADD_FAILURE() << key << " not in\n" << info.out;
    return at == std::string::npos ? -1.0 : std::stod(info.out.substr(at + key.size() + 3));
}

std::string convert(const std::string& recipe, const std::string& out, const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"convert", recipe, "-o", out, "--preset", "preview", "--no-predict", "--threads", "2"};
    args.insert(args.end(), extra.begin(), extra.end());
    const npf::testing::ToolRun r = run_tool(args);
    EXPECT_EQ(r.status, 0) << describe(r);
    return out;
}

// A clear coat (GGX alpha 0.01, dielectric) over rough aluminium: the sum of two lobes with
// different Fresnel terms is not separable, so the detail layer carries the coat's narrow peak.
TEST(DetailMeasure, HalfAngleKeepsANarrowPeakThatSolidAngleLoses) {
    const std::string dir = npf::testing::temporary_folder("detail-measure");
    const std::string recipe = dir + "/coat.yaml";
    std::ofstream(recipe) << "name: clear coat over rough aluminium\nwavelengths: 400:700:4\nlobes:\n"
                             "  - {distribution: ggx, alpha: 0.01, fresnel: {dielectric: 1.5}}\n"
                             "  - {distribution: ggx, alpha: 0.3, fresnel: {conductor: Al}, weight: 0.9}\n";
    // (Explicit: the preview preset's default is solid-angle.)
    const double half = metadata_number(convert(recipe, dir + "/half.exr", {"--detail-measure", "half-angle"}),
                                        "error_held_out_rel_rms");
    const double solid = metadata_number(convert(recipe, dir + "/solid.exr", {"--detail-measure", "solid-angle"}),
                                         "error_held_out_rel_rms");
    // Measured: 0.38 against 0.79.
    EXPECT_LT(half, 0.6 * solid) << "half-angle " << half << ", solid-angle " << solid;
}

// A colour-shifting paint (a gold flake lobe over a violet one): the layer drives dark channels
// below zero, where the clamp adds light the linear energy rows do not see.
TEST(DetailMeasure, ClampPassesHoldTheAlbedoOfTheStoredLayer) {
    const std::string dir = npf::testing::temporary_folder("detail-clamp");
    const std::string recipe = dir + "/paint.yaml";
    std::ofstream(recipe) << "name: colour-shift paint\nwavelengths: 400:700:4\nlobes:\n"
                             "  - {distribution: ggx, alpha: 0.06, fresnel: {schlick: {srgb: [0.9, 0.6, 0.1]}}, weight: 0.6}\n"
                             "  - {distribution: ggx, alpha: 0.35, fresnel: {schlick: {srgb: [0.25, 0.1, 0.6]}}, weight: 0.4}\n"
                             "diffuse: {srgb: [0.02, 0.02, 0.04]}\n";
    const double with = metadata_number(convert(recipe, dir + "/with.exr", {}), "energy_error");
    const double without = metadata_number(convert(recipe, dir + "/without.exr", {"--detail-clamp-passes", "0"}), "energy_error");
    // Measured: 0.13 % against 1.57 % (npf convert's independent albedo check).
    EXPECT_LT(with, 0.005);
    EXPECT_LT(with, 0.3 * without) << "with passes " << with << ", without " << without;
}

// On an anisotropic material the residual (no phi_h axis) is kept only where it lowers the
// held-out error of f_r cos: brushed copper at the preview preset, where it does not (measured
// 0.0046 with it, 0.0042 without), is written without it, and the figures say why.
TEST(DetailMeasure, AnisotropicLayerIsKeptOnlyWhereTheHeldOutErrorFalls) {
    const std::string dir = npf::testing::temporary_folder("detail-kept");
    const std::string out = convert(std::string(NPF_SOURCE_DIR) + "/configs/materials/brushed_copper.yaml", dir + "/c.exr", {});
    const npf::testing::ToolRun info = run_tool({"info", out});
    EXPECT_NE(info.out.find("\ndetail_not_kept: held-out relative RMS of f_r cos "), std::string::npos) << info.out;
    EXPECT_EQ(info.out.find("detail grid"), std::string::npos) << info.out;
    const npf::testing::ToolRun again =
        run_tool({"convert", std::string(NPF_SOURCE_DIR) + "/configs/materials/brushed_copper.yaml", "-o", dir + "/d.exr",
                  "--preset", "preview", "--no-predict", "--threads", "2"});
    const std::size_t at = again.out.find("held-out relative RMS of f_r cos ");
    ASSERT_NE(at, std::string::npos) << describe(again);
    double with = 0.0, without = 0.0;
    ASSERT_EQ(std::sscanf(again.out.c_str() + at, "held-out relative RMS of f_r cos %lf with it, %lf without", &with, &without), 2);
    EXPECT_GT(with, without);
    EXPECT_NEAR(without, metadata_number(dir + "/d.exr", "error_held_out_rel_rms"), 1e-4);
}

}  // namespace

namespace {

// A fit that degenerates where its weights see no data (the paper preset, no G pin, on a real
// file with a sub-degree peak) is reported as the fit's fault, with the way out, and writes
// nothing; the source is not called corrupt.
TEST(DegenerateFit, IsNamedAsTheFitsFaultAndWritesNothing) {
    const std::string source = std::string(NPF_SHARED_DATA_DIR) + "/rgl/cg_sunflower_rgb.bsdf";
    if (!std::ifstream(source)) GTEST_SKIP() << "rgl/cg_sunflower_rgb.bsdf not found in the shared data folder";
    const std::string dir = npf::testing::temporary_folder("degenerate-fit");
    const npf::testing::ToolRun r = run_tool({"convert", source, "-o", dir + "/out.exr", "--preset", "paper", "--grid",
                                              "45,1,45,90", "--g-grid", "45,1", "--no-predict", "--error-pairs", "0"});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_NE(r.err.find("the fit is degenerate: its factors could give"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--preset production"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("corrupt"), std::string::npos) << r.err;
    EXPECT_FALSE(std::ifstream(dir + "/out.exr").good());
}

}  // namespace
