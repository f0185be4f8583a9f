// Microfacet NDFs of the analytic materials: normalisation, projected area, masking, and
// sampling of D(m) cos(theta_m) by chi-square.

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

// ==== Microfacet ===========================================================================

TEST(AnalyticMicrofacet, DistributionIsNormalised) {
    for (const MicrofacetNdf& n : ndf_cases()) {
        const double integral = hemisphere_integral([&](const Vec3& m, double c) { return n.eval(m) * c; });
        EXPECT_NEAR(integral, 1.0, 1e-4) << describe(n);
    }
}

TEST(AnalyticMicrofacet, EvalIsZeroBelowHorizonAndPeaksAtNormal) {
    for (const MicrofacetNdf& n : ndf_cases()) {
        EXPECT_EQ(n.eval(Vec3(0.f, 0.f, -1.f)), 0.f);
        EXPECT_EQ(n.eval(Vec3(1.f, 0.f, 0.f)), 0.f);
        EXPECT_NEAR(n.eval(Vec3(0.f, 0.f, 1.f)), 1.0 / (kPi * n.alpha_x * n.alpha_y), 1e-3 / (n.alpha_x * n.alpha_y));
    }
}

// sigma(w) = w.z (1 + Lambda(w)) is the closed form of integral max(0, w.m) D(m) dm.
TEST(AnalyticMicrofacet, ProjectedAreaEqualsIntegral) {
    const std::vector<Vec3> dirs = {Vec3(0.f, 0.f, 1.f), npf::spherical_direction(0.5f, 0.3f),
                                    npf::spherical_direction(1.1f, 2.2f), npf::spherical_direction(1.45f, -0.8f),
                                    npf::spherical_direction(1.55f, 1.9f)};
    for (const MicrofacetNdf& n : ndf_cases()) {
        for (const Vec3& w : dirs) {
            const double integral = hemisphere_integral(
                [&](const Vec3& m, double) { return std::max(0.f, npf::dot(w, m)) * n.eval(m); });
            const double sigma = n.projected_area(w);
            EXPECT_NEAR(sigma / integral, 1.0, 1e-4) << describe(n) << " w = " << str(w);
            EXPECT_NEAR(sigma, w.z * (1.0 + n.lambda(w)), 1e-5 * sigma) << describe(n) << " w = " << str(w);
        }
    }
}

TEST(AnalyticMicrofacet, MaskingIsInUnitIntervalAndDecreasing) {
    Pcg32 rng(7);
    for (const MicrofacetNdf& n : ndf_cases()) {
        EXPECT_FLOAT_EQ(n.smith_g1(Vec3(0.f, 0.f, 1.f), Vec3(0.f, 0.f, 1.f)), 1.f) << describe(n);
        for (int i = 0; i < 2000; ++i) {
            const Vec3 w = uniform_hemisphere(rng), m = uniform_hemisphere(rng);
            const float g = n.smith_g1(w, m);
            ASSERT_TRUE(g >= 0.f && g <= 1.f) << describe(n) << " G1 = " << g;
            EXPECT_GE(n.lambda(w), 0.f);
            if (npf::dot(w, m) <= 0.f) {
                EXPECT_EQ(g, 0.f);
            }
        }
        // Along one azimuth, G1 falls from 1 at the normal to 0 at the horizon.
        float prev = 1.f;
        for (int i = 1; i <= 100; ++i) {
            const Vec3 w = npf::spherical_direction(float(0.5 * kPi * i / 100), 0.7f);
            const float g = n.smith_g1(w, Vec3(0.f, 0.f, 1.f));
            EXPECT_LE(g, prev + 1e-6f) << describe(n);
            prev = g;
        }
        EXPECT_LT(prev, 1e-5f) << describe(n);
    }
}

// The NDF sampler as a "BRDF" whose wo is the sampled normal, so that the chi-square test
// checks m ~ D(m) cos(theta_m).
class NdfSampler final : public npf::Brdf {
public:
    explicit NdfSampler(MicrofacetNdf n) : m_ndf(n) { m_info.format = "ndf"; }
    const npf::BrdfInfo& info() const override { return m_info; }
    void eval_cos(const Vec3&, const Vec3&, const ChannelQuery&, float*) const override {}
    float pdf(const Vec3&, const Vec3& wo) const override { return wo.z > 0.f ? m_ndf.eval(wo) * wo.z : 0.f; }
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery&, npf::BrdfSample& s, float*) const override {
        s.wo = m_ndf.sample(u);
        s.pdf = pdf(wi, s.wo);
        return true;
    }

private:
    MicrofacetNdf m_ndf;
    npf::BrdfInfo m_info;
};

TEST(AnalyticMicrofacet, SamplingFollowsDCos) {
    const std::vector<MicrofacetNdf> cases = {
        ndf(MicrofacetDistribution::Ggx, 0.3f, 0.3f),           ndf(MicrofacetDistribution::Ggx, 0.05f, 0.3f, 0.4f),
        ndf(MicrofacetDistribution::Ggx, 1.0f, 0.4f, -2.0f),    ndf(MicrofacetDistribution::Beckmann, 0.2f, 0.2f),
        ndf(MicrofacetDistribution::Beckmann, 0.5f, 0.06f, 1.0f)};
    for (const MicrofacetNdf& n : cases) {
        NdfSampler s(n);
        Chi2Options opt;
        opt.sample_count = 200000;
        opt.trials = int(cases.size());
        const Chi2Result r = npf::testing::run_chi2_test(s, Vec3(0.f, 0.f, 1.f), opt);
        EXPECT_TRUE(r.passed) << describe(n) << ": " << r.message;
        EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3) << describe(n);
    }
}

}  // namespace
