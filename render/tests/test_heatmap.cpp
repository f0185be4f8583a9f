// relMSE heatmaps (npf/render/heatmap.h): the colour ramp, and the PNG of a hand-made image
// pair, pixel by pixel.
#include "error_of.h"
#include "test_images.h"
#include "test_png.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/color/spectrum.h>
#include <npf/render/heatmap.h>
#include <npf/render/image_metrics.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace npf::testing::images;
using npf::testing::contains, npf::testing::error_of;

TEST(Heatmap, ColourRampFromBlueToRed) {
    using C = std::array<std::uint8_t, 3>;
    EXPECT_EQ(npf::render::heatmap_colour(0.0), (C{0, 0, 255}));
    EXPECT_EQ(npf::render::heatmap_colour(-1.0), (C{0, 0, 255}));
    EXPECT_EQ(npf::render::heatmap_colour(0.0125), (C{0, 255, 255}));
    EXPECT_EQ(npf::render::heatmap_colour(0.025), (C{0, 255, 0}));
    EXPECT_EQ(npf::render::heatmap_colour(0.0375), (C{255, 255, 0}));
    EXPECT_EQ(npf::render::heatmap_colour(0.05), (C{255, 0, 0}));
    EXPECT_EQ(npf::render::heatmap_colour(7.0), (C{255, 0, 0}));
    EXPECT_EQ(npf::render::heatmap_colour(std::nan("")), (C{255, 0, 0}));
    EXPECT_EQ(npf::render::heatmap_colour(0.00625), (C{0, 128, 255}));  // halfway blue -> cyan
    EXPECT_EQ(npf::render::heatmap_colour(0.05, 0.1), (C{0, 255, 0}));  // another scale
}

TEST(Heatmap, PngShowsRelMsePerPixelAndBlackBackground) {
    // Four pixels against a reference of 1 (relMSE = d^2 / 1.01 per channel): identical (blue),
    // d = 1 (relMSE 0.99, red), not covered in either (black), d^2 = 0.025 * 1.01 (green).
    const float mid = 1.f + float(std::sqrt(0.025 * 1.01));
    const FloatImage reference = make_image(4, 1, 4, [](std::size_t x, std::size_t) {
        return x == 2 ? std::array<float, 4>{} : std::array<float, 4>{1.f, 1.f, 1.f, 1.f};
    });
    const FloatImage test = make_image(4, 1, 4, [&](std::size_t x, std::size_t) {
        const float v = std::array<float, 4>{1.f, 2.f, 0.f, mid}[x];
        return std::array<float, 4>{v, v, v, x == 2 ? 0.f : 1.f};
    });
    const std::string dir = npf::testing::temporary_folder("heatmap");
    const std::string png = (fs::path(dir) / "heat.png").string();
    npf::render::write_relmse_heatmap(png, npf::render::relmse_map(reference, test));
    const npf::testing::Png read = npf::testing::read_png(png);
    const std::vector<unsigned char>& px = read.pixels;
    ASSERT_EQ(read.channels, 3);
    ASSERT_EQ(px.size(), 12u);
    EXPECT_EQ(std::vector<unsigned char>(px.begin(), px.begin() + 3), (std::vector<unsigned char>{0, 0, 255}));
    EXPECT_EQ(std::vector<unsigned char>(px.begin() + 3, px.begin() + 6), (std::vector<unsigned char>{255, 0, 0}));
    EXPECT_EQ(std::vector<unsigned char>(px.begin() + 6, px.begin() + 9), (std::vector<unsigned char>{0, 0, 0}));
    EXPECT_EQ(std::vector<unsigned char>(px.begin() + 9, px.begin() + 12), (std::vector<unsigned char>{0, 255, 0}));

    // Errors name the output; nothing is left behind.
    const std::string missing = (fs::path(dir) / "no_such_folder" / "heat.png").string();
    std::string e = error_of([&] { npf::render::write_relmse_heatmap(missing, npf::render::relmse_map(reference, test)); });
    EXPECT_TRUE(contains(e, missing)) << e;
    const std::string bad = (fs::path(dir) / "bad.png").string();
    e = error_of([&] { npf::render::write_relmse_heatmap(bad, npf::render::relmse_map(reference, test), 0.0); });
    EXPECT_TRUE(contains(e, bad) && contains(e, "maximum")) << e;
    EXPECT_EQ(npf::testing::folder_entries(dir), (std::vector<std::string>{"heat.png"}));
}

}  // namespace
