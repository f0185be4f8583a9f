// AnalyticBrdf: formula properties, RGB projection and queried wavelengths, reciprocity, the
// white furnace. NDFs: test_analytic_microfacet.cpp; Fresnel: test_analytic_fresnel.cpp;
// sampling against pdf and robustness: test_analytic_sampling.cpp.

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

// ==== AnalyticBrdf =========================================================================

TEST(AnalyticBrdf, InfoDescribesTheMaterial) {
    AnalyticMaterial m = one_lobe(ndf(MicrofacetDistribution::Ggx, 0.1f, 0.1f));
    m.name = "brushed thing";
    const AnalyticBrdf iso(m);
    EXPECT_EQ(iso.info().format, "analytic");
    EXPECT_EQ(iso.info().path, "");
    EXPECT_EQ(iso.info().description, "brushed thing");
    EXPECT_TRUE(iso.info().isotropic);
    ASSERT_FALSE(iso.info().channels.is_rgb());
    const std::vector<float>& wl = iso.info().channels.wavelengths();
    ASSERT_EQ(wl.size(), 195u);
    EXPECT_FLOAT_EQ(wl.front(), 360.f);
    EXPECT_FLOAT_EQ(wl.back(), 1000.f);
    EXPECT_NE(iso.single_ndf(), nullptr);

    m.specular[0].ndf.rotation = 1.0f;  // rotation alone keeps it isotropic
    EXPECT_TRUE(AnalyticBrdf(m).info().isotropic);
    m.specular.push_back(SpecularLobe{ndf(MicrofacetDistribution::Beckmann, 0.1f, 0.3f), Fresnel::one(), constant(1.0)});
    m.wavelengths = {400.f, 500.f, 600.f};
    const AnalyticBrdf aniso(m);
    EXPECT_FALSE(aniso.info().isotropic);
    EXPECT_EQ(aniso.info().channels.wavelengths(), m.wavelengths);
    EXPECT_EQ(aniso.single_ndf(), nullptr);
}

TEST(AnalyticBrdf, SingleNdfOnlyWithoutOtherNonDiffuseLobes) {
    AnalyticMaterial m = coated_plastic();
    const AnalyticBrdf b(m);
    ASSERT_NE(b.single_ndf(), nullptr);
    EXPECT_EQ(b.single_ndf()->alpha_x, 0.15f);
    m.sheen = constant(0.2);
    EXPECT_EQ(AnalyticBrdf(m).single_ndf(), nullptr);
    m.sheen = SampledSpectrum();
    m.retroreflection = constant(0.2);
    EXPECT_EQ(AnalyticBrdf(m).single_ndf(), nullptr);
    EXPECT_EQ(AnalyticBrdf(retro_and_sheen()).single_ndf(), nullptr);
}

TEST(AnalyticBrdf, QueryAcceptsRgbAndAnyWavelengths) {
    const AnalyticBrdf b(coated_plastic());
    const ChannelQuery rgb = b.query(Channels::rgb());
    EXPECT_TRUE(rgb.requested.is_rgb());
    EXPECT_EQ(rgb.size(), 3u);
    EXPECT_EQ(rgb.index1.size(), 3u);
    EXPECT_EQ(rgb.weight1.size(), 3u);
    const ChannelQuery s = spectral_query(b, {1200.f, 450.f, 450.f, 300.f});
    EXPECT_EQ(s.size(), 4u);
    EXPECT_EQ(s.requested.wavelengths().size(), 4u);
    EXPECT_EQ(b.native_query().size(), 195u);
    for (std::vector<float> bad : {std::vector<float>{}, std::vector<float>{500.f, -1.f}, std::vector<float>{NAN},
                                   std::vector<float>{0.f}, std::vector<float>{INFINITY}}) {
        try {
            b.query(Channels::spectral(bad));
            ADD_FAILURE() << "accepted a bad wavelength list";
        } catch (const npf::Error& e) {
            EXPECT_EQ(e.source(), "coated plastic");
        }
    }
}

TEST(AnalyticBrdf, ConstructorRejectsBadMaterials) {
    auto expect_error = [](AnalyticMaterial m, const char* what) {
        m.name = "bad one";
        try {
            AnalyticBrdf b(m);
            ADD_FAILURE() << "accepted " << what;
        } catch (const npf::Error& e) {
            EXPECT_EQ(e.source(), "bad one") << what;
        }
    };
    expect_error(one_lobe(ndf(MicrofacetDistribution::Ggx, 0.f, 0.1f)), "alpha 0");
    expect_error(one_lobe(ndf(MicrofacetDistribution::Ggx, NAN, 0.1f)), "alpha NaN");
    expect_error(one_lobe(ndf(MicrofacetDistribution::Ggx, 0.1f, 0.1f, INFINITY)), "rotation inf");
    expect_error(one_lobe(ndf(MicrofacetDistribution::Ggx, 0.1f, 0.1f), Fresnel::one(), constant(-1.0)), "negative weight");
    AnalyticMaterial m = coated_plastic();
    m.wavelengths = {500.f, 400.f};
    expect_error(m, "descending wavelengths");
    m = coated_plastic();
    m.retro_exponent = -1.f;
    expect_error(m, "negative exponent");
    m = coated_plastic();
    m.sheen_roughness = 0.f;
    expect_error(m, "sheen roughness 0");
}

// f(wi, wo) = f(wo, wi) for every kind of term, alone and together.
TEST(AnalyticBrdf, Reciprocity) {
    std::vector<AnalyticMaterial> ms = {
        one_lobe(ndf(MicrofacetDistribution::Ggx, 0.2f, 0.2f), gold_like()),
        one_lobe(ndf(MicrofacetDistribution::Beckmann, 0.1f, 0.4f, 0.6f), Fresnel::dielectric(constant(1.5))),
        one_lobe(ndf(MicrofacetDistribution::Ggx, 0.3f, 0.05f, -0.3f),
                 Fresnel::thin_film(400.0, constant(1.3), constant(1.5), constant(0.0))),
        one_lobe(ndf(MicrofacetDistribution::Ggx, 0.4f, 0.4f), Fresnel::schlick(ramp(0.1, 0.9))),
        coated_plastic(), retro_and_sheen(), everything(0.05f)};
    AnalyticMaterial sheen_only;
    sheen_only.sheen = constant(1.0);
    ms.push_back(sheen_only);
    AnalyticMaterial retro_only;
    retro_only.retroreflection = constant(1.0);
    retro_only.retro_exponent = 3.f;
    ms.push_back(retro_only);
    Pcg32 rng(3);
    for (const AnalyticMaterial& m : ms) {
        const AnalyticBrdf b(m);
        const ChannelQuery q = spectral_query(b, {420.f, 550.f, 680.f});
        for (int i = 0; i < 3000; ++i) {
            const Vec3 wi = uniform_hemisphere(rng), wo = uniform_hemisphere(rng);
            float a[3], c[3];
            b.eval_cos(wi, wo, q, a);
            b.eval_cos(wo, wi, q, c);
            for (int k = 0; k < 3; ++k) {
                const double f1 = a[k] / wo.z, f2 = c[k] / wi.z;
                ASSERT_NEAR(f1, f2, 2e-4 * std::max(f1, f2) + 1e-9)
                    << m.name << " wi " << str(wi) << " wo " << str(wo);
            }
        }
    }
}

TEST(AnalyticBrdf, LambertianIsAlbedoOverPi) {
    AnalyticMaterial m;
    m.name = "lambert";
    m.diffuse = ramp(0.2, 0.8);
    const AnalyticBrdf b(m);
    const std::vector<float> wl = {400.f, 475.f, 550.f, 700.f, 900.f};
    const ChannelQuery q = spectral_query(b, wl);
    Pcg32 rng(5);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 wi = uniform_hemisphere(rng), wo = uniform_hemisphere(rng);
        float v[5];
        b.eval_cos(wi, wo, q, v);
        for (int k = 0; k < 5; ++k) EXPECT_NEAR(v[k] / wo.z, m.diffuse(wl[k]) / kPi, 1e-6);
        EXPECT_NEAR(b.pdf(wi, wo), wo.z / kPi, 1e-6);
    }
}

TEST(AnalyticBrdf, RgbOfConstantDiffuseIsCosineOverPi) {
    AnalyticMaterial m;
    m.diffuse = constant(1.0);
    const AnalyticBrdf b(m);
    const ChannelQuery q = b.query(Channels::rgb());
    for (const Vec3& wo : {Vec3(0.f, 0.f, 1.f), npf::spherical_direction(1.0f, 2.0f), npf::spherical_direction(1.5f, -1.f)}) {
        float v[3];
        b.eval_cos(npf::spherical_direction(0.4f, 0.1f), wo, q, v);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[c] / (wo.z / kPi), 1.0, 2e-3) << "channel " << c;
    }
}

TEST(AnalyticBrdf, RgbFollowsTheSpectrum) {
    // A copper-coloured conductor lobe is red, and RGB equals the projection of the spectrum
    // on the 5 nm grid (checked against the colour library with the spectral path).
    const AnalyticBrdf b(one_lobe(ndf(MicrofacetDistribution::Ggx, 0.2f, 0.2f),
                                  Fresnel::conductor(ramp(1.2, 0.25), ramp(2.2, 3.6))));
    const Vec3 wi = npf::spherical_direction(0.3f, 0.f), wo = npf::spherical_direction(0.3f, float(kPi));
    float rgb[3];
    b.eval_cos(wi, wo, b.query(Channels::rgb()), rgb);
    EXPECT_GT(rgb[0], rgb[1]);
    EXPECT_GT(rgb[1], rgb[2]);
    std::vector<float> grid;
    for (int j = 0; j < 95; ++j) grid.push_back(360.f + 5.f * j);
    std::vector<float> spec(grid.size());
    b.eval_cos(wi, wo, spectral_query(b, grid), spec.data());
    const auto w = npf::color::linear_srgb_weights(grid);
    for (int c = 0; c < 3; ++c) {
        double v = 0.0;
        for (std::size_t j = 0; j < grid.size(); ++j) v += w[c][j] * spec[j];
        EXPECT_NEAR(rgb[c], v, 1e-5 * std::fabs(v) + 1e-7) << "channel " << c;
    }
}

// The material's own wavelengths are served from a precomputed table; any other list is
// looked up per call. Both must give the same numbers.
TEST(AnalyticBrdf, NativeWavelengthsMatchLookups) {
    const AnalyticBrdf b(everything(0.2f));
    const ChannelQuery native = b.native_query();
    std::vector<float> wl = b.info().channels.wavelengths();
    wl.pop_back();
    const ChannelQuery other = spectral_query(b, wl);
    std::vector<float> a(native.size()), c(other.size());
    Pcg32 rng(21);
    for (int i = 0; i < 200; ++i) {
        const Vec3 wi = uniform_hemisphere(rng), wo = uniform_hemisphere(rng);
        b.eval_cos(wi, wo, native, a.data());
        b.eval_cos(wi, wo, other, c.data());
        for (std::size_t k = 0; k < c.size(); ++k) ASSERT_NEAR(a[k], c[k], 1e-6f * a[k]) << wl[k] << " nm";
    }
}

// Wavelength lists that query() has seen are evaluated from tables made once; the values are
// those of looking the spectra up per evaluation, to the bit, also for lists beyond the tables'
// slots and for queries made concurrently.
TEST(AnalyticBrdf, QueriedWavelengthsGiveThePerEvaluationBits) {
    const AnalyticMaterial m = everything(0.2f);
    const AnalyticBrdf tabled(m), looked_up(m);
    std::vector<std::vector<float>> lists;
    for (int l = 0; l < 11; ++l) {  // more lists than slots
        std::vector<float> wl;
        for (int j = 0; j < 5 + 7 * l; ++j) wl.push_back(371.5f + float(j) * (600.f / float(5 + 7 * l)) + float(l));
        lists.push_back(wl);
    }
    std::vector<ChannelQuery> queries(lists.size());
    std::thread other([&] {
        for (std::size_t l = 1; l < lists.size(); l += 2) queries[l] = tabled.query(Channels::spectral(lists[l]));
    });
    for (std::size_t l = 0; l < lists.size(); l += 2) queries[l] = tabled.query(Channels::spectral(lists[l]));
    other.join();
    Pcg32 rng(5);
    for (std::size_t l = 0; l < lists.size(); ++l) {
        // Made by hand, without query(): this source computes every channel by looking it up.
        ChannelQuery by_hand;
        by_hand.requested = Channels::spectral(lists[l]);
        by_hand.index0.assign(lists[l].size(), 0);
        by_hand.index1.assign(lists[l].size(), 0);
        by_hand.weight1.assign(lists[l].size(), 0.f);
        std::vector<float> a(lists[l].size()), b(lists[l].size());
        for (int i = 0; i < 50; ++i) {
            const Vec3 wi = uniform_hemisphere(rng), wo = uniform_hemisphere(rng);
            tabled.eval_cos(wi, wo, queries[l], a.data());
            looked_up.eval_cos(wi, wo, by_hand, b.data());
            for (std::size_t k = 0; k < a.size(); ++k) ASSERT_EQ(a[k], b[k]) << "list " << l << ", " << lists[l][k] << " nm";
        }
    }
}

TEST(AnalyticBrdf, QuarterTurnSwapsRoughnesses) {
    for (MicrofacetDistribution t : {MicrofacetDistribution::Ggx, MicrofacetDistribution::Beckmann}) {
        const AnalyticBrdf rotated(one_lobe(ndf(t, 0.08f, 0.4f, float(0.5 * kPi)), gold_like()));
        const AnalyticBrdf swapped(one_lobe(ndf(t, 0.4f, 0.08f, 0.f), gold_like()));
        const ChannelQuery q = spectral_query(rotated, {550.f});
        Pcg32 rng(9);
        for (int i = 0; i < 3000; ++i) {
            const Vec3 wi = uniform_hemisphere(rng), wo = uniform_hemisphere(rng);
            float a, b;
            rotated.eval_cos(wi, wo, q, &a);
            swapped.eval_cos(wi, wo, q, &b);
            ASSERT_NEAR(a, b, 1e-4 * std::max(a, b) + 1e-9) << str(wi) << " " << str(wo);
            ASSERT_NEAR(rotated.pdf(wi, wo), swapped.pdf(wi, wo), 1e-4 * swapped.pdf(wi, wo) + 1e-9);
        }
        // ... and differs from the unrotated one (the test would pass for an ignored rotation).
        const AnalyticBrdf plain(one_lobe(ndf(t, 0.08f, 0.4f, 0.f), gold_like()));
        float a, b;
        // h tilted along the surface tangent, where the two lobes have different widths
        const Vec3 wi = npf::spherical_direction(0.6f, 0.f), wo = npf::spherical_direction(0.2f, float(kPi));
        plain.eval_cos(wi, wo, q, &a);
        rotated.eval_cos(wi, wo, q, &b);
        EXPECT_GT(std::fabs(a - b), 0.1f * std::max(a, b));
    }
}

TEST(AnalyticBrdf, BelowHorizonIsZero) {
    const AnalyticBrdf b(everything(0.1f));
    const ChannelQuery q = b.query(Channels::rgb());
    const Vec3 up = npf::spherical_direction(0.5f, 0.2f), down(0.3f, 0.1f, -0.948683f), flat(1.f, 0.f, 0.f);
    float v[3] = {1.f, 1.f, 1.f};
    for (auto pr : {std::pair<Vec3, Vec3>{up, down}, {down, up}, {flat, up}, {up, flat}}) {
        b.eval_cos(pr.first, pr.second, q, v);
        EXPECT_EQ(v[0] + v[1] + v[2], 0.f);
        EXPECT_EQ(b.pdf(pr.first, pr.second), 0.f);
    }
    npf::BrdfSample s;
    float w[3] = {1.f, 1.f, 1.f};
    EXPECT_FALSE(b.sample(down, Vec2{0.3f, 0.3f}, q, s, w));
    EXPECT_EQ(w[0] + w[1] + w[2], 0.f);
}

// Directional albedo of one GGX lobe with F = 1: at most 1, and close to 1 for smooth lobes.
// What is lost is single-scattering energy: facets that reflect below the horizon (at normal
// incidence a fraction alpha^2 / (1 + alpha^2) of them for GGX) and Smith masking. The
// importance-sampled estimate is cross-checked against a quadrature of eval_cos over wo.
TEST(AnalyticBrdf, WhiteFurnace) {
    struct Case {
        float alpha, theta;
        double lo;
    };
    for (Case c : {Case{0.02f, 0.f, 0.999}, Case{0.05f, 0.f, 0.995}, Case{0.05f, 1.0f, 0.985},
                   Case{0.1f, 0.f, 0.985}, Case{0.1f, 0.7f, 0.975}, Case{0.2f, 0.f, 0.93}, Case{0.2f, 1.0f, 0.88},
                   Case{0.6f, 0.5f, 0.55}}) {
        const AnalyticBrdf b(one_lobe(ndf(MicrofacetDistribution::Ggx, c.alpha, c.alpha)));
        const ChannelQuery q = spectral_query(b, {550.f});
        const Vec3 wi = npf::spherical_direction(c.theta, 0.4f);
        const int n = 400;  // stratified n x n
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j) {
                npf::BrdfSample s;
                float w = 0.f;
                b.sample(wi, Vec2{(i + 0.5f) / n, (j + 0.5f) / n}, q, s, &w);
                sum += w;
                sum2 += double(w) * w;
            }
        }
        const double mean = sum / (n * n), sd = std::sqrt(std::max(0.0, sum2 / (n * n) - mean * mean) / (n * n));
        EXPECT_LE(mean, 1.0 + 4.0 * sd + 1e-4) << "alpha " << c.alpha << " theta " << c.theta;
        EXPECT_GE(mean, c.lo) << "alpha " << c.alpha << " theta " << c.theta;
        if (c.theta == 0.f) {
            const double lost = double(c.alpha) * c.alpha / (1.0 + double(c.alpha) * c.alpha);
            EXPECT_LT(mean, 1.0 - lost + 1e-3) << "alpha " << c.alpha;
        }
        if (c.alpha >= 0.2f) {  // broad enough for the quadrature grid
            const double quad = hemisphere_integral([&](const Vec3& wo, double) {
                float v = 0.f;
                b.eval_cos(wi, wo, q, &v);
                return double(v);
            });
            EXPECT_NEAR(mean, quad, 2e-3) << "alpha " << c.alpha << " theta " << c.theta;
        }
    }
}

TEST(AnalyticBrdf, SampleWeightIsEvalOverPdf) {
    const AnalyticBrdf b(everything(0.05f));
    const ChannelQuery q = spectral_query(b, {450.f, 550.f, 650.f});
    Pcg32 rng(13);
    int ok = 0;
    for (int i = 0; i < 5000; ++i) {
        const Vec3 wi = uniform_hemisphere(rng);
        npf::BrdfSample s;
        float w[3], f[3];
        if (!b.sample(wi, Vec2{rng.next_float(), rng.next_float()}, q, s, w)) continue;
        ++ok;
        ASSERT_EQ(s.pdf, b.pdf(wi, s.wo));
        ASSERT_NEAR(npf::length(s.wo), 1.f, 1e-5f);
        b.eval_cos(wi, s.wo, q, f);
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(w[k] * s.pdf, f[k], 1e-5 * f[k] + 1e-12);
    }
    EXPECT_GT(ok, 3000);
}

}  // namespace
