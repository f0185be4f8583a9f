// End-to-end test of `npf display`: the built tool turns a linear and an XYZ OpenEXR image into
// display-encoded PNGs through the shipped OCIO config, lists the config's displays, and fails
// with status 1, a message naming the config and no file left behind for an unknown display.
#include "cli_run.h"
#include "run_tool.h"
#include "synthetic_rgl.h"
#include "test_png.h"

#include <npf/color/spectrum.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace npf::testing;  // run_tool, describe, contains, ...

const std::string kConfig = std::string(NPF_SOURCE_DIR) + "/configs/ocio/config.ocio";

TEST(CliDisplay, LinearAndXyzImagesToPng) {
    const std::string dir = npf::testing::temporary_folder("cli_display");
    // 18 % grey and white, once as linear Rec.709 and once as the same colours in XYZ.
    const npf::color::Xyz grey = npf::color::linear_srgb_to_xyz({0.18, 0.18, 0.18});
    const npf::color::Xyz white = npf::color::spectrum_to_xyz(npf::color::SampledSpectrum::constant(1.0));
    const std::string linear = (fs::path(dir) / "linear.exr").string(), xyz = (fs::path(dir) / "xyz.exr").string();
    write_float_exr(linear, {0.18f, 0.18f, 0.18f, 1.0f, 1.0f, 1.0f}, 2, 1, 3);
    write_float_exr(xyz, {float(grey[0]), float(grey[1]), float(grey[2]), float(white[0]), float(white[1]), float(white[2])}, 2, 1, 3);

    for (const auto& [input, from] : {std::pair{linear, "linear"}, std::pair{xyz, "xyz"}}) {
        const std::string png = (fs::path(dir) / (std::string(from) + ".png")).string();
        const ToolRun r = npf::testing::run_tool({"display", input, "-o", png, "--from", from, "--config", kConfig});
        ASSERT_EQ(r.status, 0) << describe(r);
        EXPECT_EQ(r.err, "") << describe(r);
        const std::vector<unsigned char> px = read_png(png).pixels;
        ASSERT_EQ(px.size(), 6u);
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(px[c], 118) << from;      // 0.4614 * 255
            EXPECT_EQ(px[3 + c], 255) << from;  // the white
        }
    }

    const ToolRun list = npf::testing::run_tool({"display", "--list", "--config", kConfig});
    ASSERT_EQ(list.status, 0) << describe(list);
    EXPECT_TRUE(contains(list.out, "display: sRGB - Display (default)")) << describe(list);
    EXPECT_TRUE(contains(list.out, "  view: Standard (default)")) << describe(list);
    EXPECT_TRUE(contains(list.out, "display: XYZ")) << describe(list);

    const std::string bad = (fs::path(dir) / "bad.png").string();
    const ToolRun r = npf::testing::run_tool({"display", linear, "-o", bad, "--config", kConfig, "--display", "Cinema"});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, kConfig) && contains(r.err, "unknown display 'Cinema'")) << describe(r);
    const ToolRun from = npf::testing::run_tool({"display", linear, "-o", bad, "--from", "aces"});
    EXPECT_EQ(from.status, 1) << describe(from);
    EXPECT_TRUE(contains(from.err, "--from")) << describe(from);
    EXPECT_FALSE(fs::exists(bad));
    for (const std::string& name : npf::testing::folder_entries(dir)) EXPECT_FALSE(contains(name, ".tmp-")) << name;
}

}  // namespace
