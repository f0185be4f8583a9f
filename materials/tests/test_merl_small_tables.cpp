// The MERL reader on small tables written here (npf::testing::write_merl): a Lambertian table,
// continuity of the linear lookup across the reciprocity fold, and invalid (negative) bins.

#include "merl_geometry.h"
#include "merl_writer.h"

#include <npf/core/error.h>
#include <npf/materials/merl_brdf.h>

#include <chi2.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace npf::testing::merl;
using npf::MerlBrdf, npf::MerlLookup, npf::Vec3;

// ---- Small tables --------------------------------------------------------------------------

// (d) A Lambertian table gives the constant f_r = stored * scale everywhere, in both modes and
// on a grid other than 90 x 90 x 180.
TEST(MerlBrdf, LambertianTable) {
    const std::string path = merl_file("lambert.binary");
    const double stored[3] = {300.0, 400.0, 500.0};
    npf::testing::write_merl(path, 9, 7, 11, [&](int, int, int, double rgb[3]) {
        for (int c = 0; c < 3; ++c) rgb[c] = stored[c];
    });
    npf::testing::Pcg32 rng(31);
    for (MerlLookup lookup : {MerlLookup::Nearest, MerlLookup::Linear}) {
        const auto brdf = MerlBrdf::load(path, {lookup});
        EXPECT_EQ(brdf->theta_d_bins(), 7);
        for (int i = 0; i < 5000; ++i) {
            const Vec3 wi = random_upper_direction(rng), wo = random_upper_direction(rng);
            if (wi.z <= 0.f || wo.z <= 0.f) continue;
            float out[3];
            brdf->eval_cos(wi, wo, rgb_query(), out);
            for (int c = 0; c < 3; ++c)
                ASSERT_FLOAT_EQ(out[c] / wo.z, static_cast<float>(stored[c] * kScale[c]));
        }
        float out[3];
        brdf->eval_cos({0.f, 0.f, 1.f}, {0.6f, 0.f, -0.8f}, rgb_query(), out);
        for (float v : out) EXPECT_EQ(v, 0.f);
        brdf->eval_cos({0.6f, 0.f, 0.f}, {0.f, 0.f, 1.f}, rgb_query(), out);
        for (float v : out) EXPECT_EQ(v, 0.f);
    }
}

// (e) Linear is continuous, also across phi_d = 0 = pi (the reciprocity fold), where the first
// and last phi_d bins meet; Nearest on the same walks jumps, which shows the check can fail.
TEST(MerlBrdf, LinearIsContinuous) {
    const std::string path = merl_file("smooth.binary");
    const int n_th = 16, n_td = 12, n_pd = 20;
    // Smooth in every index and periodic in phi_d, but not symmetric about phi_d = pi/2, so
    // clamping the phi_d ends instead of wrapping would show as a jump.
    auto value = [&](int ith, int itd, int ipd) {
        return 100.0 + 3.0 * ith + 2.0 * itd + 10.0 * std::cos(2 * kPi * (ipd + 0.5) / n_pd + 0.7);
    };
    npf::testing::write_merl(path, n_th, n_td, n_pd, [&](int ith, int itd, int ipd, double rgb[3]) {
        for (int c = 0; c < 3; ++c) rgb[c] = value(ith, itd, ipd);
    });
    const auto linear = MerlBrdf::load(path, {MerlLookup::Linear});
    const auto nearest = MerlBrdf::load(path);

    // Walks in bin coordinates (uh, ud, up) from a start, along one axis, 1e-3 bins a step.
    struct Walk {
        double uh, ud, up;
        int axis;
        double length;
    };
    const Walk walks[] = {
        {0.1, 2.3, 7.3, 0, 8.0},          // theta_h across several bins, from near the normal
        {5.6, 0.1, 13.7, 1, 7.0},         // theta_d
        {3.3, 4.4, n_pd - 2.0, 2, 4.0},   // phi_d through pi (wraps to 0)
        {3.3, 4.4, -2.0, 2, 4.0},         // phi_d through 0 from negative angles
    };
    for (const Walk& walk : walks) {
        double max_step_linear = 0, max_step_nearest = 0;
        std::array<double, 3> previous_linear{}, previous_nearest{};
        const int steps = static_cast<int>(walk.length / 1e-3);
        for (int i = 0; i <= steps; ++i) {
            double u[3] = {walk.uh, walk.ud, walk.up};
            u[walk.axis] += i * 1e-3;
            const DirectionPair p =
                pair_from_half_diff(theta_h_at(u[0], n_th), 0.9, theta_d_at(u[1], n_td),
                                    phi_d_at(u[2], n_pd));
            ASSERT_GT(p.wo.z, 0.f);
            ASSERT_GT(p.wi.z, 0.f);
            const auto l = stored_numbers(*linear, p);
            const auto n = stored_numbers(*nearest, p);
            if (i > 0) {
                max_step_linear = std::max(max_step_linear, std::fabs(l[0] - previous_linear[0]));
                max_step_nearest =
                    std::max(max_step_nearest, std::fabs(n[0] - previous_nearest[0]));
            }
            previous_linear = l;
            previous_nearest = n;
        }
        // Largest slope: 3 per bin (theta_h) or 10 * 2 pi / 20 = 3.1 per bin (phi_d).
        EXPECT_LT(max_step_linear, 0.01) << "walk along axis " << walk.axis;
        EXPECT_GT(max_step_nearest, 0.5) << "walk along axis " << walk.axis;
    }
}

// Negative stored numbers mark bins without a measurement: clamped to 0 by default, kept for
// raw queries; Linear leaves them out of the blend while a valid bin has weight.
TEST(MerlBrdf, InvalidBins) {
    const std::string path = merl_file("invalid.binary");
    const int n_th = 6, n_td = 5, n_pd = 8;
    npf::testing::write_merl(path, n_th, n_td, n_pd, [&](int, int itd, int, double rgb[3]) {
        for (int c = 0; c < 3; ++c) rgb[c] = itd == n_td - 1 ? -1.0 : 100.0;
    });
    const auto nearest = MerlBrdf::load(path);
    const auto linear = MerlBrdf::load(path, {MerlLookup::Linear});
    auto detail = [](const npf::BrdfInfo& info, const std::string& key) {
        for (const auto& kv : info.details)
            if (kv.first == key) return kv.second;
        return std::string("<missing>");
    };
    EXPECT_EQ(detail(nearest->info(), "invalid samples"), "48 of 240");

    auto eval = [&](const MerlBrdf& brdf, double ud, bool clamp) {
        const DirectionPair p = pair_from_half_diff(theta_h_at(0.5, n_th), 0.2,
                                                    theta_d_at(ud, n_td), phi_d_at(3.5, n_pd));
        EXPECT_GT(p.wo.z, 0.f);
        float out[3];
        brdf.eval_cos(p.wi, p.wo, rgb_query(clamp), out);
        std::array<double, 3> fr{};
        for (int c = 0; c < 3; ++c) fr[c] = out[c] / p.wo.z / kScale[c];
        return fr;
    };
    // In the invalid bin.
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(eval(*nearest, 4.5, true)[c], 0.0);
        EXPECT_NEAR(eval(*nearest, 4.5, false)[c], -1.0, 1e-5);
        EXPECT_NEAR(eval(*nearest, 3.5, false)[c], 100.0, 1e-4);
        // Linear between a valid and the invalid centre: the valid value, not a blend with -1.
        EXPECT_NEAR(eval(*linear, 4.2, false)[c], 100.0, 1e-4);
        // Beyond the last centre only the invalid bin has weight.
        EXPECT_NEAR(eval(*linear, 4.8, false)[c], -1.0, 1e-5);
        EXPECT_EQ(eval(*linear, 4.8, true)[c], 0.0);
    }
}

// (h) Also on a table with noisy, partly negative values.
TEST(MerlBrdf, AlwaysFiniteWithInvalidBins) {
    const std::string path = merl_file("noisy.binary");
    npf::testing::Pcg32 rng(37);
    npf::testing::write_merl(path, 10, 8, 12, [&](int, int, int, double rgb[3]) {
        for (int c = 0; c < 3; ++c)
            rgb[c] = rng.next_float() < 0.2f ? -1.0 : 1000.0 * rng.next_float();
    });
    check_always_finite(*MerlBrdf::load(path), 41, 25000);
    check_always_finite(*MerlBrdf::load(path, {MerlLookup::Linear}), 43, 25000);
}

}  // namespace
