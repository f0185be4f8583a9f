// Tests of the chi-square sampling test itself: its statistics against known values, and
// toy BRDFs showing that it passes correct samplers and fails each kind of broken one.

#include "chi2.h"

#include <npf/core/brdf.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace {

using npf::Brdf, npf::BrdfInfo, npf::BrdfSample, npf::ChannelQuery, npf::Vec2, npf::Vec3,
      npf::testing::Chi2Options, npf::testing::Chi2Result, npf::testing::chi2_sf, npf::testing::Pcg32,
      npf::testing::regularized_gamma_p, npf::testing::regularized_gamma_q, npf::testing::run_chi2_test;

constexpr float kPi = npf::kPi;

// ---- Statistics ---------------------------------------------------------------------------

TEST(Chi2Stats, GammaQOfOneIsExponential) {
    for (double x : {1e-6, 1e-3, 0.1, 0.5, 1.0, 2.0, 5.0, 20.0, 100.0, 600.0})
        EXPECT_NEAR(regularized_gamma_q(1.0, x) / std::exp(-x), 1.0, 1e-12) << "x = " << x;
}

TEST(Chi2Stats, GammaQOfOneHalfIsErfc) {
    for (double x : {1e-4, 0.01, 0.3, 1.0, 1.5, 4.0, 10.0, 50.0})
        EXPECT_NEAR(regularized_gamma_q(0.5, x) / std::erfc(std::sqrt(x)), 1.0, 1e-11)
            << "x = " << x;
}

// For integer n, Q(n, x) = e^-x sum_{k<n} x^k / k!: checks both evaluation branches.
TEST(Chi2Stats, GammaQIntegerOrderMatchesPoissonSum) {
    for (int n : {2, 3, 7, 30}) {
        for (double x : {0.05, 0.9, 2.5, 6.0, 12.0, 29.0, 31.0, 45.0}) {
            double term = 1.0, sum = 0.0;
            for (int k = 0; k < n; ++k) {
                sum += term;
                term *= x / (k + 1);
            }
            double want = std::exp(-x) * sum;
            EXPECT_NEAR(regularized_gamma_q(n, x) / want, 1.0, 1e-10) << "n=" << n << " x=" << x;
            EXPECT_NEAR(regularized_gamma_p(n, x) + regularized_gamma_q(n, x), 1.0, 1e-13);
        }
    }
}

TEST(Chi2Stats, TinyTailKeepsRelativePrecision) {
    // Q(5, 500) = e^-500 (1 + 500 + 500^2/2 + 500^3/6 + 500^4/24), about 1.9e-208.
    double log_sum = std::log(1.0 + 500.0 + 125000.0 + 125e6 / 6.0 + 625e8 / 24.0);
    double want = std::exp(-500.0 + log_sum);
    EXPECT_GT(want, 0.0);
    EXPECT_NEAR(regularized_gamma_q(5.0, 500.0) / want, 1.0, 1e-10);
    EXPECT_NEAR(chi2_sf(1000.0, 10.0) / want, 1.0, 1e-10);
}

TEST(Chi2Stats, ChiSquareSurvivalKnownQuantiles) {
    // Upper 5% and 1% points of the chi-square distribution.
    EXPECT_NEAR(chi2_sf(3.841458820694124, 1), 0.05, 1e-10);
    EXPECT_NEAR(chi2_sf(6.634896601021214, 1), 0.01, 1e-10);
    EXPECT_NEAR(chi2_sf(18.307038053275146, 10), 0.05, 1e-10);
    EXPECT_NEAR(chi2_sf(124.34211340400407, 100), 0.05, 1e-9);
    for (double x : {0.1, 1.0, 4.0, 30.0}) EXPECT_NEAR(chi2_sf(x, 2), std::exp(-0.5 * x), 1e-14);
}

TEST(Chi2Stats, EdgeCases) {
    EXPECT_EQ(regularized_gamma_q(3.0, 0.0), 1.0);
    EXPECT_EQ(regularized_gamma_p(3.0, 0.0), 0.0);
    EXPECT_EQ(chi2_sf(0.0, 4), 1.0);
    EXPECT_EQ(chi2_sf(-1.0, 4), 1.0);
    EXPECT_TRUE(std::isnan(regularized_gamma_q(0.0, 1.0)));
    EXPECT_TRUE(std::isnan(regularized_gamma_q(1.0, -1.0)));
    EXPECT_TRUE(std::isnan(chi2_sf(1.0, 0.0)));
}

TEST(Chi2Stats, Pcg32MatchesReferenceSequence) {
    // First outputs of the reference pcg32 demo, pcg32_srandom_r(&rng, 42, 54).
    Pcg32 rng(42u, 54u);
    const std::uint32_t want[] = {0xa15c02b7u, 0x7b47f409u, 0xba1d3330u,
                                  0x83d2f293u, 0xbfa4784bu, 0xcbed606eu};
    for (std::uint32_t w : want) EXPECT_EQ(rng.next_u32(), w);
    for (int i = 0; i < 1000; ++i) {
        float u = rng.next_float();
        ASSERT_GE(u, 0.f);
        ASSERT_LT(u, 1.f);
    }
}

// ---- Toy BRDFs ----------------------------------------------------------------------------

// Shared plumbing: the toys are "perfectly importance sampled", f cos = pdf, weight = 1.
class ToyBrdf : public Brdf {
public:
    ToyBrdf() { m_info.format = "toy"; }
    const BrdfInfo& info() const override { return m_info; }
    void eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query,
                  float* out) const override {
        float v = pdf(wi, wo);
        for (std::size_t k = 0; k < query.size(); ++k) out[k] = v;
    }

protected:
    static bool finish(const ChannelQuery& query, float* weight, bool ok) {
        if (weight)
            for (std::size_t k = 0; k < query.size(); ++k) weight[k] = ok ? 1.f : 0.f;
        return ok;
    }

private:
    BrdfInfo m_info;
};

Vec3 cosine_hemisphere(const Vec2& u) {
    float r = std::sqrt(u.x), phi = 2.f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::fmax(0.f, 1.f - u.x))};
}

// Lambertian: cosine-weighted sampling with the matching pdf. Correct.
class CosineBrdf : public ToyBrdf {
public:
    float pdf(const Vec3& wi, const Vec3& wo) const override {
        return wi.z > 0.f && wo.z > 0.f ? wo.z / kPi : 0.f;
    }
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                float* weight) const override {
        if (wi.z <= 0.f) return finish(query, weight, false);
        s.wo = cosine_hemisphere(u);
        s.pdf = s.wo.z / kPi;
        return finish(query, weight, s.wo.z > 0.f);
    }
};

// Samples cosine-weighted but claims a uniform hemisphere, in pdf() and s.pdf alike, so
// only the histogram can tell. Broken.
class UniformClaimBrdf : public CosineBrdf {
public:
    float pdf(const Vec3& wi, const Vec3& wo) const override {
        return wi.z > 0.f && wo.z > 0.f ? 1.f / (2.f * kPi) : 0.f;
    }
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                float* weight) const override {
        bool ok = CosineBrdf::sample(wi, u, query, s, weight);
        s.pdf = 1.f / (2.f * kPi);
        return ok;
    }
};

// Correct directions, but s.pdf 1% off pdf(). Broken in a way the histogram cannot see.
class PdfMismatchBrdf : public CosineBrdf {
public:
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                float* weight) const override {
        bool ok = CosineBrdf::sample(wi, u, query, s, weight);
        s.pdf *= 1.01f;
        return ok;
    }
};

// Fails 0.5% of the time without a pdf deficit to account for it. The remapped u keeps the
// accepted directions exactly cosine distributed, so the histogram's shape is right and the
// deficit (0.5% per cell) is too small for chi-square at 200k samples.
class DroppingBrdf : public CosineBrdf {
public:
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                float* weight) const override {
        constexpr float kDrop = 0.005f;
        if (u.x < kDrop) return finish(query, weight, false);
        Vec2 v{(u.x - kDrop) / (1.f - kDrop), u.y};
        return CosineBrdf::sample(wi, v, query, s, weight);
    }
};

// Uniform over the whole sphere, accepting directions below the horizon, while pdf()
// follows the convention (0 below). Broken: half the samples are below the horizon.
class LeakyBrdf : public ToyBrdf {
public:
    float pdf(const Vec3& wi, const Vec3& wo) const override {
        return wi.z > 0.f && wo.z > 0.f ? 1.f / (4.f * kPi) : 0.f;
    }
    bool sample(const Vec3&, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                float* weight) const override {
        float z = 1.f - 2.f * u.x, r = std::sqrt(std::fmax(0.f, 1.f - z * z));
        float phi = 2.f * kPi * u.y;
        s.wo = {r * std::cos(phi), r * std::sin(phi), z};
        s.pdf = 1.f / (4.f * kPi);
        return finish(query, weight, true);
    }
};

// Phong lobe cos^n(alpha) around the mirror direction of wi, cut off at the horizon:
// sample() fails for directions below it, so the pdf integrates to less than 1 for
// inclined wi. `claimed_exponent` lets pdf() lie about the lobe width.
class PhongBrdf : public ToyBrdf {
public:
    explicit PhongBrdf(float exponent, float claimed_exponent = -1.f)
        : m_n(exponent), m_claimed(claimed_exponent < 0.f ? exponent : claimed_exponent) {}

    float pdf(const Vec3& wi, const Vec3& wo) const override {
        if (wi.z <= 0.f || wo.z <= 0.f) return 0.f;
        float c = npf::dot(mirror(wi), wo);
        return c > 0.f ? lobe(m_claimed, c) : 0.f;
    }
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                float* weight) const override {
        if (wi.z <= 0.f) return finish(query, weight, false);
        float cos_a = std::pow(1.f - u.x, 1.f / (m_n + 1.f));  // 1 - u.x is in (0, 1]
        float sin_a = std::sqrt(std::fmax(0.f, 1.f - cos_a * cos_a));
        float phi = 2.f * kPi * u.y;
        Vec3 r = mirror(wi), t, b;
        basis(r, t, b);
        s.wo = npf::normalize(t * (sin_a * std::cos(phi)) + b * (sin_a * std::sin(phi)) +
                              r * cos_a);
        // The pdf from the drawn angle, as a real sampler would report it.
        s.pdf = lobe(m_claimed, cos_a);
        return finish(query, weight, s.wo.z > 0.f);
    }

private:
    static Vec3 mirror(const Vec3& w) { return {-w.x, -w.y, w.z}; }
    static float lobe(float n, float c) { return (n + 1.f) / (2.f * kPi) * std::pow(c, n); }
    // Orthonormal basis around unit n (Duff et al. 2017), no branch on the pole.
    static void basis(const Vec3& n, Vec3& t, Vec3& b) {
        float sign = std::copysign(1.f, n.z);
        float a = -1.f / (sign + n.z);
        float bxy = n.x * n.y * a;
        t = {1.f + sign * n.x * n.x * a, sign * bxy, -sign * n.x};
        b = {bxy, sign + n.y * n.y * a, -n.y};
    }

    float m_n, m_claimed;
};

Vec3 direction_deg(float theta_deg, float phi_deg) {
    return npf::spherical_direction(theta_deg * kPi / 180.f, phi_deg * kPi / 180.f);
}

Chi2Options toy_options() {
    Chi2Options opt;
    opt.sample_count = 200000;  // enough for the toys, keeps the file fast
    return opt;
}

// ---- Correct samplers pass ----------------------------------------------------------------

TEST(Chi2Toy, CosineSamplerPasses) {
    CosineBrdf brdf;
    Chi2Result r = run_chi2_test(brdf, direction_deg(30.f, 10.f), toy_options());
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-4);
    EXPECT_EQ(r.failed_samples, 0u);
    EXPECT_EQ(r.pdf_mismatches, 0u);
    EXPECT_GT(r.pdf_checked, 0u);
    EXPECT_GT(r.dof, 100);  // 10 x 20 upper cells, none pooled
}

TEST(Chi2Toy, CosineSamplerPassesWithWeightsAndHemisphereGrid) {
    CosineBrdf brdf;
    ChannelQuery q;  // three channels mapped one to one, built by hand
    q.index0 = {0, 1, 2};
    q.index1 = {0, 1, 2};
    q.weight1 = {0.f, 0.f, 0.f};
    Chi2Options opt = toy_options();
    opt.query = &q;
    opt.full_sphere = false;
    opt.cos_theta_bins = 8;
    opt.phi_bins = 16;
    Chi2Result r = run_chi2_test(brdf, direction_deg(0.f, 0.f), opt);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_EQ(r.rows, 8);
    EXPECT_EQ(r.cols, 16);
}

TEST(Chi2Toy, PhongLobePasses) {
    PhongBrdf brdf(40.f);
    Chi2Result r = run_chi2_test(brdf, direction_deg(35.f, 70.f), toy_options());
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_GT(r.pooled_cells, 0);  // the lobe leaves many cells nearly empty
}

// At grazing wi a good part of the lobe is below the horizon: sample() fails there and
// pdf() is 0, and the test must find the two consistent.
TEST(Chi2Toy, GrazingPhongLobeWithFailuresPasses) {
    PhongBrdf brdf(20.f);
    Chi2Result r = run_chi2_test(brdf, direction_deg(75.f, 0.f), toy_options());
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_LT(r.pdf_integral, 0.95);
    EXPECT_GT(r.failed_samples, 10000u);
    EXPECT_TRUE(r.failure_rate_ok);
    EXPECT_NEAR(r.failure_fraction, r.expected_failure_fraction, 5e-3);
}

// A near-mirror lobe: needs a finer quadrature, which the option provides.
TEST(Chi2Toy, SharpPhongLobePassesWithFineIntegration) {
    PhongBrdf brdf(3000.f);
    Chi2Options opt = toy_options();
    opt.integration_resolution = 16;
    opt.cos_theta_bins = 20;
    opt.phi_bins = 40;
    opt.full_sphere = false;  // the lobe is far from the horizon; halves the quadrature cost
    Chi2Result r = run_chi2_test(brdf, direction_deg(40.f, 200.f), opt);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3);
    EXPECT_GE(r.dof, 2);
}

// ---- Broken samplers fail, each for its own reason ----------------------------------------

TEST(Chi2Toy, WrongPdfFailsChiSquare) {
    UniformClaimBrdf brdf;
    Chi2Result r = run_chi2_test(brdf, direction_deg(30.f, 10.f), toy_options());
    EXPECT_FALSE(r.passed);
    EXPECT_LT(r.p_value, 1e-10);
    EXPECT_EQ(r.pdf_mismatches, 0u);  // s.pdf agrees with the (wrong) pdf()
    EXPECT_NE(r.message.find("worst cells"), std::string::npos) << r.message;
}

TEST(Chi2Toy, WrongLobeWidthFailsChiSquare) {
    PhongBrdf brdf(30.f, 24.f);  // samples n = 30, claims n = 24
    Chi2Result r = run_chi2_test(brdf, direction_deg(35.f, 70.f), toy_options());
    EXPECT_FALSE(r.passed) << r.message;
    EXPECT_LT(r.p_value, r.threshold);
}

TEST(Chi2Toy, SamplePdfMismatchIsReported) {
    PdfMismatchBrdf brdf;
    Chi2Result r = run_chi2_test(brdf, direction_deg(30.f, 10.f), toy_options());
    EXPECT_FALSE(r.passed);
    EXPECT_GE(r.p_value, r.threshold) << "only the pdf check should object";
    EXPECT_EQ(r.pdf_mismatches, r.pdf_checked);
    EXPECT_NEAR(r.worst_pdf_rel_error, 0.01 / 1.01, 1e-4);
    EXPECT_NE(r.message.find("s.pdf"), std::string::npos) << r.message;
}

TEST(Chi2Toy, UnexplainedSampleFailuresAreReported) {
    DroppingBrdf brdf;
    Chi2Result r = run_chi2_test(brdf, direction_deg(30.f, 10.f), toy_options());
    EXPECT_FALSE(r.passed);
    EXPECT_FALSE(r.failure_rate_ok);
    EXPECT_GE(r.p_value, r.threshold) << "only the failure-rate check should object";
    EXPECT_NEAR(r.failure_fraction, 0.005, 1e-3);
    EXPECT_NE(r.message.find("failed-sample fraction"), std::string::npos) << r.message;
}

TEST(Chi2Toy, SamplesBelowHorizonFail) {
    LeakyBrdf brdf;
    Chi2Result r = run_chi2_test(brdf, direction_deg(30.f, 10.f), toy_options());
    EXPECT_FALSE(r.passed);
    EXPECT_GT(r.below_horizon_samples, 90000u);
    EXPECT_NEAR(r.pdf_integral, 0.5, 1e-4);
    EXPECT_FALSE(r.failure_rate_ok);  // pdf misses half its mass, yet nothing failed
    EXPECT_NE(r.message.find("where pdf() integrates to 0"), std::string::npos) << r.message;

    // With only the upper hemisphere binned the leak is still caught.
    Chi2Options opt = toy_options();
    opt.full_sphere = false;
    Chi2Result h = run_chi2_test(brdf, direction_deg(30.f, 10.f), opt);
    EXPECT_FALSE(h.passed);
    EXPECT_GT(h.below_horizon_samples, 90000u);
}

}  // namespace
