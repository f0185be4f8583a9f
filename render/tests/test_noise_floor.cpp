// Noise floors (paired_noise_floor, reference_noise_floor in npf/render/image_metrics.h) on
// stand-ins for renders whose noise and error are chosen: the floor against the PSNR, the
// hand-computed constants and the three-decibel margin, the errors.
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
using npf::render::compare_images, npf::render::ImageMetrics, npf::render::MetricOptions, npf::render::NoiseFloor,
      npf::render::NoiseFloorKind, npf::testing::contains, npf::testing::error_of;

// A smooth picture in [0.16, 0.8] (away from black, where the display curve bends hardest, and
// below its clamp) plus uniform noise of the given amplitude drawn from `seed`: a stand-in for
// one render.
FloatImage render_like(std::size_t width, std::size_t height, unsigned seed, float noise, float offset = 0.f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    return make_image(width, height, 3, [&](std::size_t x, std::size_t y) {
        const float base = 0.2f + 0.6f * float(x + 2 * y) / float(width + 2 * height);
        return std::array<float, 4>{base + offset + noise * u(rng), 0.8f * base + offset + noise * u(rng),
                                    0.6f * base + 0.1f + offset + noise * u(rng), 1.f};
    });
}

// mean((e_1 - e_2)^2) / 2 with e_s = display(test_s) - display(reference_s), straight from the
// definition (docs/metrics.md), over every value.
double paired_noise_mse_by_hand(const FloatImage& r1, const FloatImage& t1, const FloatImage& r2,
                                const FloatImage& t2) {
    using npf::render::display_value;
    double sum = 0.0;
    for (std::size_t i = 0; i < r1.pixels.size(); ++i) {
        const double e1 = display_value(t1.pixels[i]) - display_value(r1.pixels[i]);
        const double e2 = display_value(t2.pixels[i]) - display_value(r2.pixels[i]);
        sum += (e1 - e2) * (e1 - e2);
    }
    return sum / double(r1.pixels.size()) / 2.0;
}

TEST(NoiseFloor, DeterministicErrorPutsTheFloorFarAboveThePsnr) {
    // Reference and test share each seed's noise (the same random numbers), the test is 0.05
    // brighter everywhere: the error barely changes from seed to seed.
    const FloatImage r1 = render_like(64, 48, 1, 0.02f), t1 = render_like(64, 48, 1, 0.02f, 0.05f);
    const FloatImage r2 = render_like(64, 48, 2, 0.02f), t2 = render_like(64, 48, 2, 0.02f, 0.05f);
    const ImageMetrics m = compare_images(r1, t1);
    const NoiseFloor f = npf::render::paired_noise_floor(r1, t1, r2, t2);
    EXPECT_EQ(f.kind, NoiseFloorKind::Paired);
    EXPECT_NEAR(f.mse_noise, paired_noise_mse_by_hand(r1, t1, r2, t2), 1e-15);
    EXPECT_DOUBLE_EQ(f.psnr, -10.0 * std::log10(f.mse_noise));
    EXPECT_GT(f.psnr - m.psnr, 25.0) << "PSNR " << m.psnr << ", floor " << f.psnr;
    EXPECT_FALSE(npf::render::noise_limited(m, f));

    // The same error without any noise: no seed noise at all, an infinite floor.
    const FloatImage c1 = render_like(64, 48, 1, 0.f), d1 = render_like(64, 48, 1, 0.f, 0.05f);
    const NoiseFloor exact = npf::render::paired_noise_floor(c1, d1, c1, d1);
    EXPECT_EQ(exact.mse_noise, 0.0);
    EXPECT_TRUE(std::isinf(exact.psnr) && exact.psnr > 0);
    EXPECT_FALSE(npf::render::noise_limited(compare_images(c1, d1), exact));
    EXPECT_FALSE(npf::render::noise_limited(compare_images(c1, c1), exact));  // identical: nothing is noise
}

TEST(NoiseFloor, PureNoisePutsTheFloorAtThePsnr) {
    // Same material, independent noise in every image: all of the measured error is noise, and
    // the floor estimates the PSNR's MSE itself (expected values equal; 27648 values, so the
    // estimates agree to a few hundredths of a dB).
    const FloatImage r1 = render_like(96, 96, 11, 0.05f), t1 = render_like(96, 96, 12, 0.05f);
    const FloatImage r2 = render_like(96, 96, 13, 0.05f), t2 = render_like(96, 96, 14, 0.05f);
    const ImageMetrics m = compare_images(r1, t1);
    const NoiseFloor f = npf::render::paired_noise_floor(r1, t1, r2, t2);
    EXPECT_NEAR(f.psnr, m.psnr, 0.2) << "PSNR " << m.psnr << ", floor " << f.psnr;
    EXPECT_TRUE(npf::render::noise_limited(m, f));

    // The reference floor is the PSNR of the reference against itself at the second seed, and
    // here (test noise like the reference's, independent) the same expected value.
    const NoiseFloor rf = npf::render::reference_noise_floor(r1, t1, r2);
    EXPECT_EQ(rf.kind, NoiseFloorKind::Reference);
    EXPECT_NEAR(rf.psnr, compare_images(r1, r2).psnr, 1e-9);  // the same sum in another order
    EXPECT_NEAR(rf.psnr, m.psnr, 0.2);
    EXPECT_STREQ(npf::render::noise_floor_kind_name(rf.kind), "reference");
    EXPECT_STREQ(npf::render::noise_floor_kind_name(f.kind), "paired");
}

TEST(NoiseFloor, HandComputedConstantsAndTheThreeDecibelMargin) {
    // Seed 1: 0.18 against 0.5 (display error 0.274000853552); seed 2: no error. e_1 - e_2 is
    // the whole seed-1 error, so the noise MSE is half the PSNR's MSE: floor = PSNR + 10 log10 2.
    const FloatImage a = constant_image(12, 12, 0.18f), b = constant_image(12, 12, 0.5f);
    const NoiseFloor f = npf::render::paired_noise_floor(a, b, a, a);
    EXPECT_NEAR(f.mse_noise, 0.2740008535520078 * 0.2740008535520078 / 2.0, 1e-8);
    EXPECT_NEAR(f.psnr, 11.2449616857565 + 10.0 * std::log10(2.0), 1e-5);
    EXPECT_NEAR(npf::render::kNoiseLimitedMarginDb, 10.0 * std::log10(2.0), 1e-15);

    // Half of the MSE is noise exactly at the margin; a little less, and the PSNR is not
    // noise-limited.
    ImageMetrics m;
    m.mse_display = 2.0 * f.mse_noise;
    EXPECT_TRUE(npf::render::noise_limited(m, f));
    m.mse_display = 2.0 * f.mse_noise * 1.001;
    EXPECT_FALSE(npf::render::noise_limited(m, f));
}

TEST(NoiseFloor, UsesThePsnrsPixelsAndCount) {
    // RGBA, 16 x 16: the left half covered at seed 1 (both images). At seed 2 a pixel on the
    // right is covered too with a large error: not one of the PSNR's pixels, so left out.
    auto image = [](float value, bool stray) {
        return make_image(16, 16, 4, [=](std::size_t x, std::size_t y) {
            const bool covered = x < 8 || (stray && x == 12 && y == 3);
            const float v = covered ? (stray && x == 12 ? 0.9f : value) : 0.f;
            return std::array<float, 4>{v, v, v, covered ? 1.f : 0.f};
        });
    };
    const FloatImage r1 = image(0.18f, false), t1 = image(0.5f, false);
    const FloatImage r2 = image(0.18f, true), t2 = image(0.18f, false);
    const ImageMetrics m = compare_images(r1, t1);
    EXPECT_EQ(m.pixels, 128u);
    const NoiseFloor f = npf::render::paired_noise_floor(r1, t1, r2, t2);
    // 128 pixels, each with e_1 - e_2 = 0.274 (seed 2 agrees): as in the constant case.
    EXPECT_NEAR(f.mse_noise, m.mse_display / 2.0, 1e-12);
    const NoiseFloor rf = npf::render::reference_noise_floor(r1, t1, r2);
    EXPECT_EQ(rf.mse_noise, 0.0);  // the reference agrees with itself on the PSNR's pixels
}

TEST(NoiseFloor, ErrorsNameTheSecondSeedImage) {
    const FloatImage a = constant_image(12, 11, 0.5f), small = constant_image(4, 4, 0.5f);
    std::string e = error_of([&] {
        npf::render::paired_noise_floor(a, a, small, a, {}, "ref.exr", "test.exr", "ref2.exr", "test2.exr");
    });
    EXPECT_EQ(e, "ref2.exr: is 4 x 4 but the reference ref.exr is 12 x 11; only images of the same size can be "
                 "compared");
    e = error_of([&] {
        npf::render::paired_noise_floor(a, a, a, small, {}, "ref.exr", "test.exr", "ref2.exr", "test2.exr");
    });
    EXPECT_TRUE(contains(e, "test2.exr: is 4 x 4 but the reference ref.exr is 12 x 11")) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    e = error_of([&] { npf::render::reference_noise_floor(a, a, small, {}, "ref.exr", "test.exr", "ref2.exr"); });
    EXPECT_TRUE(contains(e, "ref2.exr: is 4 x 4")) << e;

    const FloatImage rgba =
        make_image(12, 11, 4, [](std::size_t, std::size_t) { return std::array<float, 4>{0.5f, 0.5f, 0.5f, 1.f}; });
    e = error_of([&] {
        npf::render::paired_noise_floor(a, a, a, rgba, {}, "ref.exr", "test.exr", "ref2.exr", "test2.exr");
    });
    EXPECT_TRUE(contains(e, "test2.exr: has 4 channels") && contains(e, "ref.exr has 3")) << e;

    FloatImage nan = a;
    nan.pixels[(3 * 12 + 1) * 3] = std::nanf("");
    e = error_of([&] {
        npf::render::paired_noise_floor(a, a, nan, a, {}, "ref.exr", "test.exr", "ref2.exr", "test2.exr");
    });
    EXPECT_TRUE(contains(e, "ref2.exr: pixel (1, 3) channel R is NaN")) << e;
}

}  // namespace
