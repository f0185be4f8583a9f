// AnalyticBrdf sampling against its pdf by chi-square (AnalyticBrdfSampling), and finite,
// non-negative values everywhere, grazing and mirror pairs included.

#include "analytic_materials.h"
#include "chi2.h"

#include <npf/core/error.h>
#include <npf/core/simd_isa.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace npf::testing::analytic;

// ---- Sampling against pdf -------------------------------------------------------------------

void expect_chi2(const AnalyticMaterial& m, const std::vector<Vec3>& wis) {
    const AnalyticBrdf b(m);
    const ChannelQuery q = spectral_query(b, {450.f, 550.f, 650.f});
    for (const Vec3& wi : wis) {
        Chi2Options opt;
        opt.sample_count = 250000;
        opt.trials = int(wis.size());
        opt.query = &q;
        const Chi2Result r = npf::testing::run_chi2_test(b, wi, opt);
        EXPECT_TRUE(r.passed) << m.name << ", wi = " << str(wi) << ": " << r.message;
        EXPECT_EQ(r.invalid_samples, 0u) << m.name;
        EXPECT_EQ(r.pdf_mismatches, 0u) << m.name;
    }
}

std::vector<Vec3> chi2_directions() {
    return {npf::spherical_direction(0.f, 0.f), npf::spherical_direction(0.7f, 0.5f),
            npf::spherical_direction(1.3f, -2.0f)};
}

TEST(AnalyticBrdfSampling, RoughIsotropicGgxConductor) {
    AnalyticMaterial m = one_lobe(ndf(MicrofacetDistribution::Ggx, 0.5f, 0.5f), gold_like());
    m.name = "rough GGX conductor";
    expect_chi2(m, chi2_directions());
}

TEST(AnalyticBrdfSampling, SharpAnisotropicRotatedGgx) {
    AnalyticMaterial m = one_lobe(ndf(MicrofacetDistribution::Ggx, 0.05f, 0.3f, 0.4f), gold_like());
    m.name = "sharp anisotropic GGX";
    expect_chi2(m, chi2_directions());
}

TEST(AnalyticBrdfSampling, Beckmann) {
    AnalyticMaterial m = one_lobe(ndf(MicrofacetDistribution::Beckmann, 0.25f, 0.1f, -0.8f),
                                  Fresnel::schlick(ramp(0.5, 0.9)));
    m.name = "Beckmann";
    expect_chi2(m, chi2_directions());
}

TEST(AnalyticBrdfSampling, CoatedPlastic) { expect_chi2(coated_plastic(), chi2_directions()); }

// Two lobes at a grazing wi, where many specular draws end below the horizon (failures that
// the pdf's missing mass must account for exactly).
TEST(AnalyticBrdfSampling, TwoLobesWithFailures) {
    const AnalyticMaterial m = two_lobes();
    expect_chi2(m, {npf::spherical_direction(1.4f, 0.3f), npf::spherical_direction(1.1f, 2.5f)});
    const AnalyticBrdf b(m);
    const Chi2Result r = npf::testing::run_chi2_test(b, npf::spherical_direction(1.4f, 0.3f),
                                                     [] { Chi2Options o; o.sample_count = 100000; return o; }());
    EXPECT_GT(r.failure_fraction, 0.05) << "the case is meant to have failing draws: " << r.message;
}

TEST(AnalyticBrdfSampling, RetroAndSheen) {
    expect_chi2(retro_and_sheen(), chi2_directions());
}

// ---- Robustness -----------------------------------------------------------------------------

Vec3 at(float z, float phi) {
    const float r = std::sqrt(std::max(0.f, 1.f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

TEST(AnalyticBrdf, FiniteAndNonNegativeEverywhere) {
    Pcg32 rng(17);
    for (float alpha : {1e-3f, 0.02f}) {
        const AnalyticBrdf b(everything(alpha));
        const ChannelQuery spec = spectral_query(b, {380.f, 480.f, 550.f, 610.f, 700.f, 950.f});
        ChannelQuery raw = b.query(Channels::rgb());
        raw.clamp_negative = false;
        const ChannelQuery rgb = b.query(Channels::rgb());
        float v[6], w[6];
        double max_value = 0.0;
        for (int i = 0; i < 100000; ++i) {
            // Directions: random, exact normal, grazing (z = 1e-6), and mirror pairs.
            auto pick = [&]() -> Vec3 {
                const float r = rng.next_float(), phi = float(2.0 * kPi) * rng.next_float();
                if (r < 0.1f) return Vec3(0.f, 0.f, 1.f);
                if (r < 0.3f) return at(1e-6f, phi);
                return uniform_hemisphere(rng);
            };
            const Vec3 wi = pick();
            Vec3 wo = pick();
            if (i % 4 == 0) wo = Vec3(-wi.x, -wi.y, wi.z);  // exact mirror: D at its peak
            b.eval_cos(wi, wo, spec, v);
            for (int k = 0; k < 6; ++k) {
                ASSERT_TRUE(std::isfinite(v[k]) && v[k] >= 0.f) << "wi " << str(wi) << " wo " << str(wo) << " -> " << v[k];
                max_value = std::max(max_value, double(v[k]));
            }
            const float p = b.pdf(wi, wo);
            ASSERT_TRUE(std::isfinite(p) && p >= 0.f) << "wi " << str(wi) << " wo " << str(wo) << " pdf " << p;
            if (i % 10 == 0) {  // RGB is ~30x the work: a tenth of the pairs
                b.eval_cos(wi, wo, rgb, v);
                for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(v[k]) && v[k] >= 0.f) << str(wi) << str(wo);
                b.eval_cos(wi, wo, raw, v);
                for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(v[k])) << str(wi) << str(wo);
            }
            npf::BrdfSample s;
            if (b.sample(wi, Vec2{rng.next_float(), rng.next_float()}, spec, s, w)) {
                ASSERT_TRUE(s.wo.z > 0.f && std::isfinite(s.pdf) && s.pdf > 0.f) << str(wi) << " -> " << str(s.wo);
                for (int k = 0; k < 6; ++k)
                    ASSERT_TRUE(std::isfinite(w[k]) && w[k] >= 0.f) << str(wi) << " -> " << str(s.wo) << " " << w[k];
            }
        }
        // Mirror pairs of the sharpest lobe reach D ~ 1 / (pi alpha^2).
        if (alpha == 1e-3f) {
            EXPECT_GT(max_value, 1e4);
        }
    }
}

}  // namespace
