// The fitter's geometry: Rusinkiewicz half/difference angles and the grid's volume weight.
#include <npf/fit/rusinkiewicz.h>
#include <npf/core/vec.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

using npf::HalfDiff, npf::RusinkiewiczGrid, npf::Vec3d;

Vec3d random_upper(std::mt19937& rng, double z_min = 1e-3) {
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const double z = z_min + (1.0 - z_min) * uni(rng), phi = 2.0 * npf::kPiD * uni(rng);
    const double r = std::sqrt(1.0 - z * z);
    return {r * std::cos(phi), r * std::sin(phi), z};
}

double angle_between(const Vec3d& a, const Vec3d& b) {
    const double d = std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z));
    return 2.0 * std::asin(std::fmin(1.0, 0.5 * d));
}

TEST(Rusinkiewicz, RoundTripAndPaperEquations) {
    std::mt19937 rng(1);
    for (int i = 0; i < 100000; ++i) {
        const Vec3d wi = random_upper(rng), wo = random_upper(rng);
        const HalfDiff a = npf::half_diff_from_directions(wi, wo);
        ASSERT_GE(a.theta_h, 0.0);
        ASSERT_LE(a.theta_h, 0.5 * npf::kPiD + 1e-12);
        ASSERT_LE(a.theta_d, 0.5 * npf::kPiD + 1e-12);
        Vec3d ri, ro;
        npf::directions_from_half_diff(a, ri, ro);
        EXPECT_LT(angle_between(wi, ri), 1e-9) << i;
        EXPECT_LT(angle_between(wo, ro), 1e-9) << i;
        // Paper Eqs. 8 and 9.
        const double ci = std::cos(a.theta_h) * std::cos(a.theta_d) - std::sin(a.theta_h) * std::sin(a.theta_d) * std::cos(a.phi_d);
        const double co = std::cos(a.theta_h) * std::cos(a.theta_d) + std::sin(a.theta_h) * std::sin(a.theta_d) * std::cos(a.phi_d);
        EXPECT_NEAR(ci, wi.z, 1e-9);
        EXPECT_NEAR(co, wo.z, 1e-9);
    }
}

TEST(Rusinkiewicz, SwappingTheDirectionsTurnsPhiDByPi) {
    std::mt19937 rng(2);
    for (int i = 0; i < 10000; ++i) {
        const Vec3d wi = random_upper(rng, 0.05), wo = random_upper(rng, 0.05);
        const HalfDiff a = npf::half_diff_from_directions(wi, wo), b = npf::half_diff_from_directions(wo, wi);
        EXPECT_NEAR(a.theta_h, b.theta_h, 1e-12);
        EXPECT_NEAR(a.theta_d, b.theta_d, 1e-12);
        if (a.theta_h < 1e-6 || a.theta_d < 1e-6) continue;  // phi undefined at the poles
        EXPECT_NEAR(std::remainder(a.phi_h - b.phi_h, 2.0 * npf::kPiD), 0.0, 1e-9);
        EXPECT_NEAR(std::remainder(b.phi_d - a.phi_d - npf::kPiD, 2.0 * npf::kPiD), 0.0, 1e-9);
    }
}

TEST(Rusinkiewicz, MirrorAndRetroConfigurations) {
    // A mirror pair has theta_h = 0; retro-reflection (wi = wo) has theta_d = 0.
    const Vec3d wi{0.6, 0.0, 0.8}, mirror{-0.6, 0.0, 0.8};
    EXPECT_NEAR(npf::half_diff_from_directions(wi, mirror).theta_h, 0.0, 1e-12);
    EXPECT_NEAR(npf::half_diff_from_directions(wi, mirror).theta_d, std::acos(0.8), 1e-12);
    EXPECT_NEAR(npf::half_diff_from_directions(wi, wi).theta_d, 0.0, 1e-12);
    EXPECT_NEAR(npf::half_diff_from_directions(wi, wi).theta_h, std::acos(0.8), 1e-12);
}

TEST(Rusinkiewicz, GridSamplesSitAtCellCentres) {
    const RusinkiewiczGrid g;  // the paper's grid
    EXPECT_EQ(g.size(), std::size_t(90) * 180 * 90 * 180);
    EXPECT_FALSE(g.isotropic());
    EXPECT_NEAR(g.theta_h_at(0), 0.5 * npf::kPiD * (0.5 / 90) * (0.5 / 90), 1e-15);
    EXPECT_LT(g.theta_h_at(89), 0.5 * npf::kPiD);
    EXPECT_NEAR(std::sqrt(g.theta_h_at(45) / (0.5 * npf::kPiD)), 45.5 / 90, 1e-12) << "uniform in sqrt(theta_h)";
    EXPECT_NEAR(g.theta_d_at(89), 0.5 * npf::kPiD * 89.5 / 90, 1e-12);
    EXPECT_NEAR(g.phi_d_at(0), npf::kPiD / 180, 1e-12);
    RusinkiewiczGrid iso{90, 1, 90, 180};
    EXPECT_TRUE(iso.isotropic());
    EXPECT_EQ(iso.phi_h_at(0), 0.0);
}

// Summed over the samples whose directions are both above the horizon, the volume weights
// give the measure of those direction pairs, (2 pi)^2: the check that Eq. 4 and the
// square-root Jacobian are right.
TEST(Rusinkiewicz, VolumeWeightsIntegrateThePairsOfDirections) {
    for (const RusinkiewiczGrid& g : {RusinkiewiczGrid{48, 64, 48, 96}, RusinkiewiczGrid{48, 1, 48, 96}}) {
        double total = 0.0, all = 0.0;
        for (int ih = 0; ih < g.theta_h; ++ih) {
            for (int id = 0; id < g.theta_d; ++id) {
                const double w = g.volume_weight(ih, id);
                for (int jh = 0; jh < g.phi_h; ++jh) {
                    for (int jd = 0; jd < g.phi_d; ++jd) {
                        const HalfDiff a{g.theta_h_at(ih), g.phi_h_at(jh), g.theta_d_at(id), g.phi_d_at(jd)};
                        Vec3d wi, wo;
                        npf::directions_from_half_diff(a, wi, wo);
                        all += w;
                        if (wi.z > 0.0 && wo.z > 0.0) total += w;
                    }
                }
            }
        }
        const double pairs = 4.0 * npf::kPiD * npf::kPiD;
        EXPECT_NEAR(total / pairs, 1.0, 0.01) << "phi_h cells " << g.phi_h;
        // Over the whole parameter domain the closed form is
        // 4 * int sin(th) dth * int dphi_h * int sin(td) cos(td) dtd * int dphi_d = 4 * 1 * 2pi * 1/2 * 2pi = 8 pi^2.
        EXPECT_NEAR(all / (8.0 * npf::kPiD * npf::kPiD), 1.0, 0.01) << "phi_h cells " << g.phi_h;
    }
}

}  // namespace
