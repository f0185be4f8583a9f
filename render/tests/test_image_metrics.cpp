// Image metrics (npf/render/image_metrics.h) and relMSE heatmaps (npf/render/heatmap.h) on
// image pairs whose answers are computed by hand: identical images, constant offsets, scaled
// images, constant images for SSIM, noise, permuted pixels, the alpha rule, the error cases.
// The expected numbers come from the definitions in docs/metrics.md, evaluated separately
// (Python, double precision) where a literal is given.
// Heatmaps: test_heatmap.cpp; noise floors: test_noise_floor.cpp.
#include "error_of.h"
#include "test_images.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/color/spectrum.h>
#include <npf/render/heatmap.h>
#include <npf/render/image_metrics.h>

#include <OpenImageIO/imageio.h>
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
using npf::render::compare_images, npf::render::Coverage, npf::render::ImageMetrics, npf::render::MetricOptions,
      npf::testing::contains, npf::testing::error_of;

TEST(ImageMetrics, DisplayValueIsTheSrgbTransferClamped) {
    EXPECT_NEAR(npf::render::display_value(0.18), 0.46135612950044164, 1e-15);
    EXPECT_NEAR(npf::render::display_value(0.5), 0.7353569830524495, 1e-15);
    EXPECT_NEAR(npf::render::display_value(0.002), 0.02584, 1e-15);  // linear segment, 12.92 v
    EXPECT_EQ(npf::render::display_value(0.0), 0.0);
    EXPECT_EQ(npf::render::display_value(-3.0), 0.0);
    EXPECT_DOUBLE_EQ(npf::render::display_value(1.0), 1.0);
    EXPECT_DOUBLE_EQ(npf::render::display_value(40.0), 1.0);
}

TEST(ImageMetrics, IdenticalImagesGiveInfinitePsnrAndPerfectScores) {
    const FloatImage rgb = noise_image(17, 13, 1);
    const ImageMetrics m = compare_images(rgb, rgb);
    EXPECT_TRUE(std::isinf(m.psnr) && m.psnr > 0) << m.psnr;
    EXPECT_EQ(m.ssim, 1.0);
    EXPECT_EQ(m.relmse, 0.0);
    EXPECT_EQ(m.mape, 0.0);
    EXPECT_EQ(m.mse_display, 0.0);
    EXPECT_EQ(m.pixels, 17u * 13u);
    EXPECT_EQ(m.pixels_total, 17u * 13u);

    // With alpha: a disc, covered pixels only.
    const FloatImage rgba = make_image(20, 20, 4, [](std::size_t x, std::size_t y) {
        const float dx = float(x) - 9.5f, dy = float(y) - 9.5f, a = dx * dx + dy * dy < 49.f ? 1.f : 0.f;
        return std::array<float, 4>{a * 0.3f * float(x), a * 0.1f, a * 0.05f * float(y), a};
    });
    const ImageMetrics ma = compare_images(rgba, rgba);
    EXPECT_TRUE(std::isinf(ma.psnr));
    EXPECT_EQ(ma.ssim, 1.0);
    EXPECT_EQ(ma.relmse, 0.0);
    EXPECT_EQ(ma.mape, 0.0);
    EXPECT_GT(ma.pixels, 100u);
    EXPECT_LT(ma.pixels, 400u);
}

TEST(ImageMetrics, ConstantOffsetGivesPsnrOfTheDisplayDifference) {
    // 0.18 and 0.5 display as 0.461356129500 and 0.735356983052: MSE = 0.274000853552^2.
    const FloatImage reference = constant_image(16, 16, 0.18f), test = constant_image(16, 16, 0.5f);
    const ImageMetrics m = compare_images(reference, test);
    EXPECT_NEAR(m.mse_display, 0.2740008535520078 * 0.2740008535520078, 1e-8);
    EXPECT_NEAR(m.psnr, 11.2449616857565, 1e-5);
    EXPECT_NEAR(m.psnr, psnr_of(0.2740008535520078), 1e-5);

    // On the linear segment: 0.002 displays as 12.92 * 0.002 (float 0.002f: 0.0258400012).
    const ImageMetrics dark = compare_images(constant_image(11, 11, 0.f), constant_image(11, 11, 0.002f));
    EXPECT_NEAR(dark.psnr, 31.75414940098146, 1e-9);

    // The same offset on half the pixels only halves the MSE: + 10 log10(2) dB.
    const FloatImage half = make_image(16, 16, 3, [](std::size_t x, std::size_t) {
        const float v = x < 8 ? 0.5f : 0.18f;
        return std::array<float, 4>{v, v, v, 1.f};
    });
    EXPECT_NEAR(compare_images(reference, half).psnr, psnr_of(0.2740008535520078, 0.5), 1e-5);
    EXPECT_NEAR(compare_images(reference, half).psnr - m.psnr, 10.0 * std::log10(2.0), 1e-9);

    // Black against white: MSE 1, PSNR 0.
    EXPECT_NEAR(compare_images(constant_image(11, 11, 0.f), constant_image(11, 11, 1.f)).psnr, 0.0, 1e-12);
}

TEST(ImageMetrics, ScaledImageGivesRelMseAndMapeInClosedForm) {
    // Checkerboard of 0.125 and 0.75 (exact in float), test = 1.5 x reference (also exact).
    const std::array<double, 2> values = {0.125, 0.75};
    const FloatImage reference = make_image(12, 12, 3, [&](std::size_t x, std::size_t y) {
        const float v = float(values[(x + y) % 2]);
        return std::array<float, 4>{v, v, v, 1.f};
    });
    for (const double k : {1.5, 0.5, 3.0}) {
        const ImageMetrics m = compare_images(reference, scaled(reference, float(k)));
        double relmse = 0.0, mape = 0.0;
        for (const double r : values) {
            relmse += 0.5 * (k - 1) * (k - 1) * r * r / (r * r + 0.01);
            mape += 0.5 * std::abs(k - 1) * r / (r + 0.01);
        }
        EXPECT_NEAR(m.relmse, relmse, 1e-12) << k;
        EXPECT_NEAR(m.mape, mape, 1e-12) << k;
    }
    // k = 1.5 by hand: relMSE (0.25 * 0.015625 / 0.025625 + 0.25 * 0.5625 / 0.5725) / 2,
    // MAPE (0.5 * 0.125 / 0.135 + 0.5 * 0.75 / 0.76) / 2.
    const ImageMetrics m = compare_images(reference, scaled(reference, 1.5f));
    EXPECT_NEAR(m.relmse, 0.19903610608158484, 1e-12);
    EXPECT_NEAR(m.mape, 0.4781920077972709, 1e-12);
}

TEST(ImageMetrics, HighlightsAboveOneCountInRelMseButNotInDisplayMetrics) {
    // 2 and 5 both display as 1: PSNR and SSIM cannot see them; relMSE and MAPE do.
    const ImageMetrics m = compare_images(constant_image(12, 12, 2.f), constant_image(12, 12, 5.f));
    EXPECT_TRUE(std::isinf(m.psnr));
    EXPECT_EQ(m.ssim, 1.0);
    EXPECT_NEAR(m.relmse, 9.0 / 4.01, 1e-12);
    EXPECT_NEAR(m.mape, 3.0 / 2.01, 1e-12);
}

TEST(ImageMetrics, SsimOfConstantImagesFollowsTheLuminanceTerm) {
    // Constant images: no variance, so SSIM = (2 a b + C1) / (a^2 + b^2 + C1), C1 = 1e-4, with a
    // and b the display values (0.461356129500, 0.735356983052): 0.9003893718627382.
    const ImageMetrics m = compare_images(constant_image(15, 12, 0.18f), constant_image(15, 12, 0.5f));
    EXPECT_NEAR(m.ssim, 0.9003893718627382, 1e-7);
    // Black against 0.02584: C1 / (0.02584^2 + C1).
    const ImageMetrics dark = compare_images(constant_image(15, 12, 0.f), constant_image(15, 12, 0.002f));
    EXPECT_NEAR(dark.ssim, 0.13025825490643464, 1e-9);
    // SSIM is averaged where the 11 x 11 window fits: (15 - 10) x (12 - 10) pixels here; an
    // image smaller than 11 x 11 has none.
    EXPECT_EQ(m.ssim_pixels, 10u);
    EXPECT_EQ(m.pixels, 180u);
    const std::string e = error_of([&] {
        compare_images(constant_image(30, 10, 0.18f), constant_image(30, 10, 0.5f), {}, "ref.exr", "test.exr");
    });
    EXPECT_TRUE(contains(e, "test.exr") && contains(e, "at least 11 x 11")) << e;
}

TEST(ImageMetrics, SsimIsSymmetricAndBelowOneForNoise) {
    const FloatImage a = noise_image(24, 20, 7), b = noise_image(24, 20, 8);
    const ImageMetrics ab = compare_images(a, b), ba = compare_images(b, a);
    EXPECT_NEAR(ab.ssim, ba.ssim, 1e-15);
    EXPECT_LT(ab.ssim, 0.99);
    EXPECT_GT(ab.ssim, 0.0);
    EXPECT_NEAR(ab.psnr, ba.psnr, 1e-12);  // the MSE is symmetric; relMSE and MAPE are not
    EXPECT_NE(ab.relmse, ba.relmse);

    // A little noise on top of an image: close to 1, but below it, and more noise is worse.
    FloatImage slightly = a, more = a;
    std::mt19937 rng(3);
    std::normal_distribution<float> n(0.f, 1.f);
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        const float e = n(rng);
        slightly.pixels[i] += 0.005f * e;
        more.pixels[i] += 0.05f * e;
    }
    const double s1 = compare_images(a, slightly).ssim, s2 = compare_images(a, more).ssim;
    EXPECT_LT(s1, 1.0);
    EXPECT_GT(s1, 0.9);
    EXPECT_LT(s2, s1);
}

TEST(ImageMetrics, PixelMetricsAreInvariantUnderPixelPermutationSsimIsNot) {
    const FloatImage reference = noise_image(16, 16, 11, 0.05f);
    FloatImage test = reference;
    std::mt19937 rng(5);
    std::normal_distribution<float> n(0.f, 0.1f);
    for (float& v : test.pixels) v += n(rng);
    std::vector<std::size_t> order(16 * 16);
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);

    const ImageMetrics m = compare_images(reference, test);
    const ImageMetrics p = compare_images(permuted(reference, order), permuted(test, order));
    EXPECT_NEAR(p.psnr, m.psnr, 1e-10 * m.psnr);
    EXPECT_NEAR(p.relmse, m.relmse, 1e-12 * m.relmse);
    EXPECT_NEAR(p.mape, m.mape, 1e-12 * m.mape);
    EXPECT_EQ(p.pixels, m.pixels);
    // SSIM compares neighbourhoods: scrambling them changes it.
    EXPECT_GT(std::abs(p.ssim - m.ssim), 1e-3) << m.ssim << " " << p.ssim;
}

// 16 x 16 RGBA: the left half covered in both (identical colour 0.5); the right half has alpha
// 0 in both, the reference black there and the test a stray 0.9 (say, a background that the
// renderer did not clear); one pixel of the right half, (12, 6), is covered in the test only,
// with colour 0.3.
std::pair<FloatImage, FloatImage> alpha_pair() {
    const FloatImage reference = make_image(16, 16, 4, [](std::size_t x, std::size_t) {
        return x < 8 ? std::array<float, 4>{0.5f, 0.5f, 0.5f, 1.f} : std::array<float, 4>{0.f, 0.f, 0.f, 0.f};
    });
    const FloatImage test = make_image(16, 16, 4, [](std::size_t x, std::size_t y) {
        if (x < 8) return std::array<float, 4>{0.5f, 0.5f, 0.5f, 1.f};
        if (x == 12 && y == 6) return std::array<float, 4>{0.3f, 0.3f, 0.3f, 1.f};
        return std::array<float, 4>{0.9f, 0.9f, 0.9f, 0.f};
    });
    return {reference, test};
}

TEST(ImageMetrics, AlphaRuleComparesPixelsCoveredInEitherImage) {
    const auto [reference, test] = alpha_pair();
    const ImageMetrics m = compare_images(reference, test);
    EXPECT_EQ(m.pixels, 129u);  // 128 covered in both, 1 in the test only; 127 left out
    EXPECT_EQ(m.pixels_total, 256u);
    EXPECT_EQ(m.ssim_pixels, 3u * 6u);  // where the window fits, x and y in 5..10: columns 5..7
    const double r = 0.3f;      // the float 0.3
    EXPECT_NEAR(m.relmse, (r * r / 0.01) / 129.0, 1e-12);
    EXPECT_NEAR(m.mape, (r / 0.01) / 129.0, 1e-12);
    EXPECT_NEAR(m.psnr, 25.780146630004705, 1e-9);  // display(0.3) = 0.58383150064, MSE = that^2 / 129
    EXPECT_LT(m.ssim, 1.0);

    // Every pixel: the stray background counts (relMSE 0.81 / 0.01 = 81 on each of 31 pixels).
    MetricOptions all;
    all.coverage = Coverage::AllPixels;
    const ImageMetrics a = compare_images(reference, test, all);
    EXPECT_EQ(a.pixels, 256u);
    EXPECT_NEAR(a.relmse, (r * r / 0.01 + 127.0 * double(0.9f) * double(0.9f) / 0.01) / 256.0, 1e-12);

    // The map: uncovered pixels flagged and 0, the odd pixel 9.
    const npf::render::RelMseMap map = npf::render::relmse_map(reference, test);
    ASSERT_EQ(map.values.size(), 256u);
    EXPECT_EQ(std::count(map.covered.begin(), map.covered.end(), 1), 129);
    EXPECT_EQ(map.covered[6 * 16 + 12], 1);
    EXPECT_NEAR(map.values[6 * 16 + 12], r * r / 0.01, 1e-12);
    EXPECT_EQ(map.covered[6 * 16 + 13], 0);
    EXPECT_EQ(map.values[6 * 16 + 13], 0.0);
    EXPECT_EQ(map.values[0], 0.0);

    // Nothing covered anywhere: an error, not a silent perfect score.
    const FloatImage empty = make_image(11, 11, 4, [](std::size_t, std::size_t) { return std::array<float, 4>{}; });
    const std::string e = error_of([&] { compare_images(empty, empty, {}, "ref.exr", "test.exr"); });
    EXPECT_TRUE(contains(e, "test.exr") && contains(e, "ref.exr") && contains(e, "alpha is 0")) << e;
    EXPECT_EQ(compare_images(empty, empty, all).pixels, 121u);
}

TEST(ImageMetrics, SsimAveragesTheMapOverComparedPixelsOnly) {
    // 40 x 16 grey RGBA: columns 0..11 covered, 0.18 against 0.5; columns 12..39 alpha 0 and
    // identical (0.3). Far from the covered block the map is 1; across the edge (up in the
    // reference, down in the test) it is low. The means run over the pixels 5 or more from
    // every border (the window fits): columns 5..11 (covered) or 5..34 (all), rows 5..10.
    const FloatImage reference = make_image(40, 16, 4, [](std::size_t x, std::size_t) {
        return x < 12 ? std::array<float, 4>{0.18f, 0.18f, 0.18f, 1.f} : std::array<float, 4>{0.3f, 0.3f, 0.3f, 0.f};
    });
    const FloatImage test = make_image(40, 16, 4, [](std::size_t x, std::size_t) {
        return x < 12 ? std::array<float, 4>{0.5f, 0.5f, 0.5f, 1.f} : std::array<float, 4>{0.3f, 0.3f, 0.3f, 0.f};
    });
    std::vector<double> dr, dt;
    for (std::size_t i = 0; i < 40 * 16; ++i) {
        dr.push_back(npf::render::display_value(reference.pixels[i * 4]));
        dt.push_back(npf::render::display_value(test.pixels[i * 4]));
    }
    const std::vector<double> map = npf::render::ssim_map(dr, dt, 40, 16);
    double covered = 0.0, all = 0.0;
    for (std::size_t y = 5; y <= 10; ++y)
        for (std::size_t x = 5; x <= 34; ++x) {
            all += map[y * 40 + x] / (6.0 * 30.0);
            if (x <= 11) covered += map[y * 40 + x] / (6.0 * 7.0);
        }
    const ImageMetrics m = compare_images(reference, test);
    EXPECT_EQ(m.pixels, 12u * 16u);
    EXPECT_EQ(m.ssim_pixels, 6u * 7u);
    EXPECT_NEAR(m.ssim, covered, 1e-12);
    MetricOptions every;
    every.coverage = Coverage::AllPixels;
    EXPECT_NEAR(compare_images(reference, test, every).ssim, all, 1e-12);
    EXPECT_GT(std::abs(all - covered), 0.05) << all << " " << covered;
    // Deep inside the covered block the window sees constants: the luminance term alone.
    EXPECT_NEAR(map[8 * 40 + 5], 0.9003893718627382, 1e-6);
}

TEST(ImageMetrics, XyzInputIsConvertedToLinearRec709First) {
    const npf::color::Xyz grey = npf::color::linear_srgb_to_xyz({0.18, 0.18, 0.18});
    const npf::color::Xyz light = npf::color::linear_srgb_to_xyz({0.5, 0.5, 0.5});
    auto xyz_image = [](const npf::color::Xyz& c) {
        return make_image(12, 12, 3, [&](std::size_t, std::size_t) {
            return std::array<float, 4>{float(c[0]), float(c[1]), float(c[2]), 1.f};
        });
    };
    MetricOptions options;
    options.input = npf::color::SceneSpace::CieXyzD65;
    const ImageMetrics m = compare_images(xyz_image(grey), xyz_image(light), options);
    EXPECT_NEAR(m.psnr, 11.2449616857565, 1e-5);
    EXPECT_NEAR(m.relmse, 0.32 * 0.32 / (0.18 * 0.18 + 0.01), 1e-6);
    // Read as linear RGB, the same files give other numbers.
    EXPECT_GT(std::abs(compare_images(xyz_image(grey), xyz_image(light)).psnr - m.psnr), 0.01);
}

TEST(ImageMetrics, ErrorsNameTheFileAndTheProblem) {
    const FloatImage a = constant_image(8, 8, 0.5f), b = constant_image(8, 6, 0.5f);
    std::string e = error_of([&] { compare_images(a, b, {}, "ref.exr", "test.exr"); });
    EXPECT_TRUE(contains(e, "test.exr: is 8 x 6 but the reference ref.exr is 8 x 8")) << e;

    const FloatImage rgba = make_image(8, 8, 4, [](std::size_t, std::size_t) { return std::array<float, 4>{0.5f, 0.5f, 0.5f, 1.f}; });
    e = error_of([&] { compare_images(a, rgba, {}, "ref.exr", "test.exr"); });
    EXPECT_TRUE(contains(e, "test.exr: has 4 channels") && contains(e, "ref.exr has 3")) << e;

    FloatImage nan = a;
    nan.pixels[(2 * 8 + 5) * 3 + 1] = std::nanf("");
    e = error_of([&] { compare_images(a, nan, {}, "ref.exr", "test.exr"); });
    EXPECT_TRUE(contains(e, "test.exr: pixel (5, 2) channel G is NaN")) << e;
    e = error_of([&] { compare_images(nan, a, {}, "ref.exr", "test.exr"); });
    EXPECT_TRUE(contains(e, "ref.exr: pixel (5, 2) channel G is NaN")) << e;

    FloatImage inf = rgba;
    inf.pixels[7 * 4 + 3] = -INFINITY;
    e = error_of([&] { compare_images(rgba, inf, {}, "ref.exr", "test.exr"); });
    EXPECT_TRUE(contains(e, "test.exr: pixel (7, 0) channel A is infinite")) << e;

    FloatImage short_buffer = a;
    short_buffer.pixels.pop_back();
    e = error_of([&] { compare_images(short_buffer, a, {}, "ref.exr", "test.exr"); });
    EXPECT_TRUE(contains(e, "ref.exr: holds 191 values, not 8 x 8 x 3")) << e;

    FloatImage two = a;
    two.channels = 2;
    e = error_of([&] { compare_images(a, two, {}, "ref.exr", "test.exr"); });
    EXPECT_TRUE(contains(e, "test.exr: has 2 channels")) << e;

    const FloatImage none = constant_image(0, 5, 0.f);
    e = error_of([&] { compare_images(none, none, {}, "ref.exr", "test.exr"); });
    EXPECT_TRUE(contains(e, "test.exr: is empty")) << e;
}

TEST(ImageMetrics, SsimMapIsOneForEqualPlanesAndHandlesTinyImages) {
    const std::vector<double> x = {0.1, 0.7, 0.3, 0.9, 0.0, 0.5};
    for (const double v : npf::render::ssim_map(x, x, 3, 2)) EXPECT_EQ(v, 1.0);
    const std::vector<double> single = npf::render::ssim_map({0.2}, {0.4}, 1, 1);
    ASSERT_EQ(single.size(), 1u);
    EXPECT_NEAR(single[0], (2 * 0.2 * 0.4 + 1e-4) / (0.04 + 0.16 + 1e-4), 1e-15);
    EXPECT_TRUE(contains(error_of([&] { npf::render::ssim_map(x, x, 2, 2); }), "ssim_map"));
}

TEST(ImageMetrics, MatchesScikitImageOnASmoothPair) {
    // Reference numbers from scikit-image 0.26 on the same images (float32, then the sRGB
    // transfer in float64): structural_similarity(display_ref, display_test, channel_axis=-1,
    // gaussian_weights=True, sigma=1.5, use_sample_covariance=False, data_range=1.0) and
    // peak_signal_noise_ratio(..., data_range=1.0); relMSE and MAPE with numpy.
    auto ref_value = [](std::size_t x, std::size_t y, int c) {
        return float(0.5 + 0.4 * std::sin(0.7 * double(x) + 1.3 * double(y) + c));
    };
    const FloatImage reference = make_image(16, 14, 3, [&](std::size_t x, std::size_t y) {
        return std::array<float, 4>{ref_value(x, y, 0), ref_value(x, y, 1), ref_value(x, y, 2), 1.f};
    });
    const FloatImage test = make_image(16, 14, 3, [&](std::size_t x, std::size_t y) {
        std::array<float, 4> p{};
        for (int c = 0; c < 3; ++c)
            p[std::size_t(c)] = float(double(ref_value(x, y, c)) + 0.1 * std::cos(1.1 * double(x) - 0.6 * double(y) + 2 * c));
        return p;
    });
    // Tolerances: sin and cos of numpy and the C library may round a pixel to a neighbouring
    // float (about 1e-9 in the means).
    const ImageMetrics m = compare_images(reference, test);
    EXPECT_NEAR(m.ssim, 0.9446781081785548, 1e-8);
    EXPECT_NEAR(m.psnr, 22.798037440941677, 1e-6);
    EXPECT_NEAR(m.relmse, 0.06123643440254908, 1e-8);
    EXPECT_NEAR(m.mape, 0.20250771958694364, 1e-8);
    EXPECT_EQ(m.ssim_pixels, 6u * 4u);
}

TEST(ImageMetrics, SsimWindowIsTheGaussianOfRadius5AndSigma1_5) {
    // x: a single 1 in zeros; y: all zeros. Where the window weight of the 1 is w (the weights
    // normalised to sum 1), mu_x = w, sigma_x^2 = w - w^2, mu_y = sigma_y^2 = sigma_xy = 0, so
    // SSIM = C1 C2 / ((w^2 + C1)(w - w^2 + C2)). 1-D weights exp(-k^2 / 4.5), k = -5..5, sum
    // S = 3.759232795169263; cut to k = 0..5 at a border: 2.3796163975846314.
    std::vector<double> x(21 * 21, 0.0), y(21 * 21, 0.0);
    x[10 * 21 + 10] = 1.0;
    const std::vector<double> map = npf::render::ssim_map(x, y, 21, 21);
    EXPECT_NEAR(map[10 * 21 + 10], 0.0002643743162066147, 1e-12);  // w = 1 / S^2
    EXPECT_NEAR(map[10 * 21 + 11], 0.0005001818155645012, 1e-12);  // w = exp(-1/4.5) / S^2
    EXPECT_EQ(map[0], 1.0);                                         // the window does not reach the 1
    std::vector<double> corner(11 * 11, 0.0);
    corner[0] = 1.0;
    const std::vector<double> cut = npf::render::ssim_map(corner, std::vector<double>(11 * 11, 0.0), 11, 11);
    EXPECT_NEAR(cut[0], 1.9660852132970456e-05, 1e-13);  // w = 1 / 2.3796163975846314^2
}

}  // namespace
