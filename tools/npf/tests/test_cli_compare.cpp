// End-to-end test of `npf compare`: the built tool on OpenEXR pairs with known answers (identical,
// a constant offset, alpha coverage), its JSON output, the heatmap PNG, and the errors (status 1,
// a message naming the file, nothing written).
#include "cli_run.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace npf::testing;  // run_tool, describe, contains, ...

std::string constant_exr(const std::string& dir, const std::string& name, float value, int width = 12, int height = 11) {
    const std::string path = (fs::path(dir) / name).string();
    write_float_exr(path, std::vector<float>(std::size_t(width * height * 3), value), width, height, 3);
    return path;
}

// The number after "KEY " on its own line, or NaN.
double line_value(const std::string& out, const std::string& key) {
    for (const std::string& line : npf::testing::lines_of(out))
        if (line.rfind(key + " ", 0) == 0) return std::strtod(line.c_str() + key.size() + 1, nullptr);
    return std::nan("");
}

TEST(CliCompare, IdenticalImagesPrintInfAndPerfectScores) {
    const std::string dir = npf::testing::temporary_folder("cli_compare");
    const std::string a = constant_exr(dir, "a.exr", 0.3f), b = constant_exr(dir, "b.exr", 0.3f);
    const ToolRun r = npf::testing::run_tool({"compare", a, b});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(r.err, "") << describe(r);
    const std::vector<std::string> lines = npf::testing::lines_of(r.out);
    ASSERT_GE(lines.size(), 4u) << describe(r);
    EXPECT_EQ(lines[0], "PSNR inf");
    EXPECT_EQ(lines[1], "SSIM 1");
    EXPECT_EQ(lines[2], "relMSE 0");
    EXPECT_EQ(lines[3], "MAPE 0");
    EXPECT_TRUE(has_line(r.out, "pixels 132")) << describe(r);
    EXPECT_TRUE(has_line(r.out, "pixels_total 132")) << describe(r);
    EXPECT_TRUE(has_line(r.out, "ssim_pixels 2")) << describe(r);  // (12 - 10) x (11 - 10)

    const ToolRun j = npf::testing::run_tool({"compare", a, b, "--json"});
    ASSERT_EQ(j.status, 0) << describe(j);
    EXPECT_EQ(npf::testing::lines_of(j.out).size(), 1u) << describe(j);
    EXPECT_TRUE(contains(j.out, "\"PSNR\": \"inf\", \"SSIM\": 1, \"relMSE\": 0, \"MAPE\": 0, \"pixels\": 132"))
        << describe(j);
    EXPECT_EQ(j.out.front(), '{');
    EXPECT_TRUE(contains(j.out, "\"reference\": \"" + a + "\"")) << describe(j);
}

TEST(CliCompare, ConstantOffsetAndScaleGiveHandComputedValues) {
    const std::string dir = npf::testing::temporary_folder("cli_compare");
    // 0.18 and 0.5: display values 0.461356129500 and 0.735356983052 (docs/metrics.md).
    const std::string ref = constant_exr(dir, "ref.exr", 0.18f), test = constant_exr(dir, "test.exr", 0.5f);
    const ToolRun r = npf::testing::run_tool({"compare", ref, test});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NEAR(line_value(r.out, "PSNR"), 11.2449616857565, 1e-5) << describe(r);
    EXPECT_NEAR(line_value(r.out, "SSIM"), 0.9003893718627382, 1e-7) << describe(r);
    EXPECT_NEAR(line_value(r.out, "relMSE"), 0.32 * 0.32 / (0.18 * 0.18 + 0.01), 1e-6) << describe(r);
    EXPECT_NEAR(line_value(r.out, "MAPE"), 0.32 / 0.19, 1e-6) << describe(r);

    const ToolRun j = npf::testing::run_tool({"compare", ref, test, "--json"});
    ASSERT_EQ(j.status, 0) << describe(j);
    const std::size_t at = j.out.find("\"PSNR\": ");
    ASSERT_NE(at, std::string::npos) << describe(j);
    EXPECT_NEAR(std::strtod(j.out.c_str() + at + 8, nullptr), 11.2449616857565, 1e-5) << describe(j);
}

TEST(CliCompare, AlphaCoverageAndHeatmap) {
    const std::string dir = npf::testing::temporary_folder("cli_compare");
    // 12 x 12 RGBA. Columns 0..5 covered in both, 0.5, except pixel (2, 5) which is 1.5 in the
    // test; columns 6..11 alpha 0 in both, 0 in the reference and a stray 0.7 in the test (left
    // out unless --all-pixels).
    std::vector<float> ref_px, test_px;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 12; ++x) {
            const bool covered = x < 6;
            const float r = covered ? 0.5f : 0.f, t = covered ? (x == 2 && y == 5 ? 1.5f : 0.5f) : 0.7f;
            const float a = covered ? 1.f : 0.f;
            ref_px.insert(ref_px.end(), {r, r, r, a});
            test_px.insert(test_px.end(), {t, t, t, a});
        }
    const std::string ref = (fs::path(dir) / "ref.exr").string(), test = (fs::path(dir) / "test.exr").string();
    write_float_exr(ref, ref_px, 12, 12, 4);
    write_float_exr(test, test_px, 12, 12, 4);
    const std::string png = (fs::path(dir) / "heat.png").string();
    const ToolRun r = npf::testing::run_tool({"compare", ref, test, "--heatmap", png});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(has_line(r.out, "pixels 72")) << describe(r);
    EXPECT_TRUE(has_line(r.out, "pixels_total 144")) << describe(r);
    EXPECT_NEAR(line_value(r.out, "relMSE"), 1.0 / 0.26 / 72.0, 1e-7) << describe(r);  // 1^2 / (0.25 + 0.01) once

    auto pixel = [](const std::vector<unsigned char>& px, int x, int y) {
        const std::size_t i = std::size_t(y * 12 + x) * 3;
        return std::vector<unsigned char>(px.begin() + long(i), px.begin() + long(i) + 3);
    };
    auto in = OIIO::ImageInput::open(png);
    ASSERT_TRUE(in) << OIIO::geterror();
    ASSERT_EQ(in->spec().nchannels, 3);
    std::vector<unsigned char> px(12 * 12 * 3);
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeUInt8, px.data()));
    EXPECT_EQ(pixel(px, 0, 0), (std::vector<unsigned char>{0, 0, 255}));  // relMSE 0: blue
    EXPECT_EQ(pixel(px, 2, 5), (std::vector<unsigned char>{255, 0, 0}));  // 3.85: red
    EXPECT_EQ(pixel(px, 8, 3), (std::vector<unsigned char>{0, 0, 0}));    // not compared: black

    // Every pixel: the stray 0.7 counts (0.49 / 0.01 = 49 each), and a heatmap scale of 2 / 0.26
    // shows the odd pixel's 1 / 0.26 halfway: green.
    const ToolRun all = npf::testing::run_tool(
        {"compare", ref, test, "--all-pixels", "--json", "--heatmap", png, "--heatmap-max", "7.6923"});
    ASSERT_EQ(all.status, 0) << describe(all);
    EXPECT_TRUE(contains(all.out, "\"pixels\": 144, \"pixels_total\": 144, \"ssim_pixels\": 4, \"coverage\": \"all\""))
        << describe(all);
    auto again = OIIO::ImageInput::open(png);
    ASSERT_TRUE(again) << OIIO::geterror();
    ASSERT_TRUE(again->read_image(0, 0, 0, 3, OIIO::TypeUInt8, px.data()));
    EXPECT_EQ(pixel(px, 2, 5), (std::vector<unsigned char>{0, 255, 0}));
    EXPECT_EQ(pixel(px, 8, 3), (std::vector<unsigned char>{255, 0, 0}));
    EXPECT_EQ(pixel(px, 0, 0), (std::vector<unsigned char>{0, 0, 255}));
}

TEST(CliCompare, ErrorsNameTheFile) {
    const std::string dir = npf::testing::temporary_folder("cli_compare");
    const std::string ref = constant_exr(dir, "ref.exr", 0.2f), small = constant_exr(dir, "small.exr", 0.2f, 4, 4);
    const std::string heat = (fs::path(dir) / "heat.png").string();

    ToolRun r = npf::testing::run_tool({"compare", ref, small, "--heatmap", heat});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "npf compare: error: " + small + ": is 4 x 4 but the reference " + ref + " is 12 x 11"))
        << describe(r);
    EXPECT_EQ(r.out, "");

    const std::string missing = (fs::path(dir) / "missing.exr").string();
    r = npf::testing::run_tool({"compare", missing, ref});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "npf compare: error: " + missing + ": ")) << describe(r);

    const std::string nan = (fs::path(dir) / "nan.exr").string();
    std::vector<float> px(12 * 11 * 3, 0.2f);
    px[(1 * 12 + 2) * 3 + 2] = std::nanf("");
    write_float_exr(nan, px, 12, 11, 3);
    r = npf::testing::run_tool({"compare", ref, nan});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "npf compare: error: " + nan + ": pixel (2, 1) channel B is NaN")) << describe(r);

    const std::string rgba = (fs::path(dir) / "rgba.exr").string();
    write_float_exr(rgba, std::vector<float>(12 * 11 * 4, 1.f), 12, 11, 4);
    r = npf::testing::run_tool({"compare", ref, rgba});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, rgba + ": has 4 channels")) << describe(r);

    r = npf::testing::run_tool({"compare", ref, ref, "--heatmap-max", "0"});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "--heatmap-max")) << describe(r);
    r = npf::testing::run_tool({"compare", ref, ref, "--from", "aces"});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "--from")) << describe(r);

    const std::string nowhere = (fs::path(dir) / "no_such_folder" / "heat.png").string();
    r = npf::testing::run_tool({"compare", ref, ref, "--heatmap", nowhere});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, nowhere)) << describe(r);

    EXPECT_FALSE(fs::exists(heat));
    for (const std::string& name : npf::testing::folder_entries(dir)) EXPECT_FALSE(contains(name, ".tmp")) << name;
}

TEST(CliCompare, HelpAndUsage) {
    const ToolRun help = npf::testing::run_tool({"compare", "--help"});
    EXPECT_EQ(help.status, 0) << describe(help);
    EXPECT_TRUE(contains(help.out, "usage: npf compare REF.exr TEST.exr")) << describe(help);
    EXPECT_TRUE(contains(help.out, "--heatmap")) << describe(help);
    const ToolRun one = npf::testing::run_tool({"compare", "only.exr"});
    EXPECT_EQ(one.status, 2) << describe(one);
    const ToolRun bad = npf::testing::run_tool({"compare", "a.exr", "b.exr", "--psnr-peak", "2"});
    EXPECT_EQ(bad.status, 1) << describe(bad);
    EXPECT_TRUE(contains(bad.err, "unknown option '--psnr-peak'")) << describe(bad);
}

TEST(CliCompare, FloorKeepsTheOutputAndAddsTheNoiseFloor) {
    const std::string dir = npf::testing::temporary_folder("cli_compare");
    // Seed 1: 0.18 against 0.5. Seed 2: 0.18 against 0.45, so e_1 - e_2 = d(0.5) - d(0.45) and
    // the floor is -10 log10((d(0.5) - d(0.45))^2 / 2) = 32.3944577 dB (docs/metrics.md).
    const std::string ref = constant_exr(dir, "ref.exr", 0.18f), test = constant_exr(dir, "test.exr", 0.5f);
    const std::string ref2 = constant_exr(dir, "ref2.exr", 0.18f), test2 = constant_exr(dir, "test2.exr", 0.45f);

    const ToolRun plain = npf::testing::run_tool({"compare", ref, test});
    const ToolRun r = npf::testing::run_tool({"compare", ref, test, "--floor", ref2, test2});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(r.err, "") << describe(r);
    // The lines without --floor come first, unchanged.
    ASSERT_EQ(r.out.rfind(plain.out, 0), 0u) << describe(r);
    EXPECT_NEAR(line_value(r.out, "noise_floor_db"), 32.39445774370758, 1e-5) << describe(r);
    EXPECT_TRUE(has_line(r.out, "noise_floor_kind paired")) << describe(r);
    EXPECT_TRUE(has_line(r.out, "noise_limited no")) << describe(r);
    EXPECT_TRUE(contains(r.out, "summary: PSNR 11.24 dB, noise floor 32.39 dB (paired): the PSNR measures the "
                                "materials' difference"))
        << describe(r);

    // --floor may come first; the text is the same.
    const ToolRun first = npf::testing::run_tool({"compare", "--floor", ref2, test2, ref, test});
    ASSERT_EQ(first.status, 0) << describe(first);
    EXPECT_EQ(first.out, r.out);

    // JSON: the object without --floor, then the floor's fields.
    const ToolRun plain_json = npf::testing::run_tool({"compare", ref, test, "--json"});
    const ToolRun j = npf::testing::run_tool({"compare", ref, test, "--json", "--floor", ref2, test2});
    ASSERT_EQ(j.status, 0) << describe(j);
    ASSERT_GE(plain_json.out.size(), 2u);
    const std::string without_close = plain_json.out.substr(0, plain_json.out.size() - 2);  // less "}\n"
    ASSERT_EQ(j.out.rfind(without_close + ", \"noise_floor_db\": ", 0), 0u) << describe(j);
    const std::size_t at = j.out.find("\"noise_floor_db\": ");
    EXPECT_NEAR(std::strtod(j.out.c_str() + at + 18, nullptr), 32.39445774370758, 1e-5) << describe(j);
    EXPECT_TRUE(contains(j.out, "\"noise_floor_kind\": \"paired\"")) << describe(j);
    EXPECT_TRUE(contains(j.out, "\"noise_limited\": false")) << describe(j);
    EXPECT_TRUE(contains(j.out, "\"floor_reference\": \"" + ref2 + "\", \"floor_test\": \"" + test2 + "\"}"))
        << describe(j);
    EXPECT_EQ(npf::testing::lines_of(j.out).size(), 1u) << describe(j);
}

TEST(CliCompare, FloorSaysWhenThePsnrMeasuresNoise) {
    const std::string dir = npf::testing::temporary_folder("cli_compare");
    // Seed 2 swaps the images: e_2 = -e_1, so the noise MSE is 2 e_1^2, twice the PSNR's MSE:
    // floor = PSNR - 10 log10 2 = 8.2346620 dB, and the PSNR is noise.
    const std::string a = constant_exr(dir, "a.exr", 0.18f), b = constant_exr(dir, "b.exr", 0.5f);
    const ToolRun r = npf::testing::run_tool({"compare", a, b, "--floor", b, a});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_NEAR(line_value(r.out, "noise_floor_db"), 8.234662000129195, 1e-5) << describe(r);
    EXPECT_TRUE(has_line(r.out, "noise_limited yes")) << describe(r);
    EXPECT_TRUE(contains(r.out, "(paired): at or above the floor, so at least half of the measured error is seed "
                                "noise"))
        << describe(r);

    // Seed 2: 0.18 against 0.15, a small error of the other sign: the floor lies 1.9 dB above the
    // PSNR (e_1 - e_2 = d(0.5) - d(0.15)).
    const std::string c = constant_exr(dir, "c.exr", 0.15f);
    const ToolRun below = npf::testing::run_tool({"compare", a, b, "--floor", a, c});
    ASSERT_EQ(below.status, 0) << describe(below);
    EXPECT_TRUE(has_line(below.out, "noise_limited yes")) << describe(below);
    EXPECT_TRUE(contains(below.out, "less than 3 dB below the floor")) << describe(below);
    const double gap = line_value(below.out, "noise_floor_db") - line_value(below.out, "PSNR");
    EXPECT_GT(gap, 0.0) << describe(below);
    EXPECT_LT(gap, 3.0) << describe(below);

    // Unpaired: the reference against itself at the second seed (here b): the PSNR of a against b.
    const ToolRun u = npf::testing::run_tool({"compare", a, b, "--floor", b, "--json"});
    ASSERT_EQ(u.status, 0) << describe(u);
    const std::size_t at = u.out.find("\"noise_floor_db\": ");
    ASSERT_NE(at, std::string::npos) << describe(u);
    EXPECT_NEAR(std::strtod(u.out.c_str() + at + 18, nullptr), 11.244961956769007, 1e-5) << describe(u);
    EXPECT_TRUE(contains(u.out, "\"noise_floor_kind\": \"reference\"")) << describe(u);
    EXPECT_TRUE(contains(u.out, "\"noise_limited\": true")) << describe(u);
    EXPECT_FALSE(contains(u.out, "floor_test")) << describe(u);
    const ToolRun ut = npf::testing::run_tool({"compare", a, b, "--floor", b});
    EXPECT_TRUE(has_line(ut.out, "noise_floor_kind reference")) << describe(ut);
    EXPECT_TRUE(contains(ut.out, "the paired floor, --floor REF2.exr TEST2.exr, sees less noise")) << describe(ut);
}

TEST(CliCompare, FloorErrors) {
    const std::string dir = npf::testing::temporary_folder("cli_compare");
    const std::string ref = constant_exr(dir, "ref.exr", 0.2f), test = constant_exr(dir, "test.exr", 0.3f);
    const std::string small = constant_exr(dir, "small.exr", 0.2f, 4, 4);

    // A second-seed image of another size: one line naming it, no numbers, no heatmap.
    const std::string heat = (fs::path(dir) / "heat.png").string();
    ToolRun r = npf::testing::run_tool({"compare", ref, test, "--floor", small, test, "--heatmap", heat});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_EQ(r.err, "npf compare: error: " + small + ": is 4 x 4 but the reference " + ref +
                         " is 12 x 11; only images of the same size can be compared\n")
        << describe(r);
    EXPECT_EQ(r.out, "");
    EXPECT_FALSE(fs::exists(heat));
    r = npf::testing::run_tool({"compare", ref, test, "--floor", ref, small, "--json"});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, small + ": is 4 x 4")) << describe(r);
    EXPECT_EQ(npf::testing::lines_of(r.err).size(), 1u) << describe(r);
    EXPECT_EQ(r.out, "");

    r = npf::testing::run_tool({"compare", ref, test, "--floor"});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "--floor: needs one or two images")) << describe(r);
    r = npf::testing::run_tool({"compare", ref, test, "--floor", "--json"});
    EXPECT_EQ(r.status, 1) << describe(r);
    r = npf::testing::run_tool({"compare", ref, "--floor", ref, test});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "give REF.exr TEST.exr before --floor")) << describe(r);
    r = npf::testing::run_tool({"compare", ref, test, "--floor", ref, "--floor", test});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "--floor: given twice")) << describe(r);
    // The first seed's files again: no noise, an infinite floor, and a warning.
    r = npf::testing::run_tool({"compare", ref, test, "--floor", ref, test});
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(has_line(r.out, "noise_floor_db inf")) << describe(r);
    EXPECT_TRUE(contains(r.err, "npf compare: warning: --floor: the second seed's images give exactly")) << describe(r);

    const std::string missing = (fs::path(dir) / "missing.exr").string();
    r = npf::testing::run_tool({"compare", ref, test, "--floor", missing});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, missing)) << describe(r);
}

}  // namespace
