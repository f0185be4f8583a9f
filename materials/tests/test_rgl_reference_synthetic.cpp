// RglBrdf against NaiveRgl (support/rgl_reference.h) on synthetic files of every kind the
// reader supports (RglReferenceSynthetic), and its interpolation between stored wavelengths
// (RglReferenceSpectral).
#include "rgl_reference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using namespace npf::testing::rgl_reference;

// ---- (c) Synthetic kinds versus NaiveRgl ----------------------------------------------------

void run_synthetic_comparison(const std::string& kind) {
    const Material& m = synthetic_material(kind);
    // The loaders agree on what kind of file this is.
    EXPECT_EQ(m.brdf->info().isotropic, m.naive->isotropic) << kind;
    EXPECT_EQ(m.brdf->reduction(), m.naive->reduction) << kind;
    EXPECT_EQ(m.brdf->jacobian(), m.naive->jacobian) << kind;

    const auto pairs = comparison_pairs(6000, std::hash<std::string>()(kind));
    expect_agreement(compare_with_naive(m, pairs, {}, 99), kind);
    if (m.naive->spectral) {
        // Between the stored wavelengths (400, 500, 600, 700 nm), at and beyond the ends.
        const std::vector<double> between = {450.0, 512.5, 599.0, 683.25};
        const std::vector<double> outside = {300.0, 399.0, 700.0, 701.0, 1000.0};
        expect_agreement(compare_with_naive(m, pairs, between, 100), kind + " (between)");
        expect_agreement(compare_with_naive(m, pairs, outside, 101), kind + " (outside)");
    }
}

TEST(RglReferenceSynthetic, IsotropicRgb) { run_synthetic_comparison("iso_rgb"); }
TEST(RglReferenceSynthetic, IsotropicSpectral) { run_synthetic_comparison("iso_spectral"); }
TEST(RglReferenceSynthetic, IsotropicJacobian0) { run_synthetic_comparison("iso_rgb_jacobian0"); }
TEST(RglReferenceSynthetic, IsotropicPhiCount2) { run_synthetic_comparison("iso_phi_count2"); }
TEST(RglReferenceSynthetic, AnisotropicR1Rgb) { run_synthetic_comparison("aniso_r1_rgb"); }
TEST(RglReferenceSynthetic, AnisotropicR2Rgb) { run_synthetic_comparison("aniso_r2_rgb"); }
TEST(RglReferenceSynthetic, AnisotropicR4Rgb) { run_synthetic_comparison("aniso_r4_rgb"); }
TEST(RglReferenceSynthetic, AnisotropicR1Spectral) { run_synthetic_comparison("aniso_r1_spectral"); }
TEST(RglReferenceSynthetic, AnisotropicR2Spectral) { run_synthetic_comparison("aniso_r2_spectral"); }
TEST(RglReferenceSynthetic, AnisotropicR4Spectral) { run_synthetic_comparison("aniso_r4_spectral"); }
TEST(RglReferenceSynthetic, AnisotropicR2Jacobian0) { run_synthetic_comparison("aniso_r2_jacobian0"); }

// Every synthetic kind has a test above.
TEST(RglReferenceSynthetic, EveryKindIsCovered) { EXPECT_EQ(synthetic_kinds().size(), 11u); }

// Spectral evaluation at in-between wavelengths is the linear blend of the neighbouring
// stored ones, and constant outside the stored range (sec. 8), checked on the reader alone.
TEST(RglReferenceSpectral, WavelengthInterpolationIsLinearAndClamped) {
    const Material& m = synthetic_material("aniso_r2_spectral");
    const auto q = m.brdf->query(npf::Channels::spectral({400.f, 500.f, 450.f, 470.f, 350.f,
                                                          700.f, 800.f}));
    const auto pairs = comparison_pairs(500, 7);
    for (const Pair& p : pairs) {
        float v[7];
        m.brdf->eval_cos(p.wi, p.wo, q, v);
        const double scale = std::max({1e-30, double(std::fabs(v[0])), double(std::fabs(v[1]))});
        EXPECT_NEAR(v[2], 0.5 * (v[0] + v[1]), 1e-6 * scale) << str(p.wi) << " " << str(p.wo);
        EXPECT_NEAR(v[3], 0.3 * v[0] + 0.7 * v[1], 1e-6 * scale) << str(p.wi) << " " << str(p.wo);
        EXPECT_EQ(v[4], v[0]);
        EXPECT_EQ(v[6], v[5]);
    }
}

}  // namespace
