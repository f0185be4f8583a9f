// npf::directional_albedo (docs/albedo.md): exact on Lambertian materials (rho for the analytic
// diffuse term, pi rho_d for an NPF model's), a sampler that misses energy cannot hide it,
// mirror-sharp and rough microfacet lobes agree with an independent half-vector quadrature up
// to grazing 89 degrees and stay at most 1, the results are bit-identical run to run and for
// any thread count, and bad input is refused.
#include "error_of.h"
#include "npf_test_factors.h"
#include "synthetic_rgl.h"

#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/fit/spectral_compression.h>
#include <npf/materials/open_material.h>
#include <npf/core/directional_albedo.h>
#include <npf/core/error.h>
#include <npf/shading/npf_brdf.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace {

using npf::AlbedoRow, npf::AlbedoTableOptions, npf::AnalyticBrdf, npf::AnalyticMaterial, npf::Brdf,
      npf::ChannelQuery, npf::Channels, npf::DirectionalAlbedoOptions, npf::Vec2, npf::Vec3,
      npf::color::SampledSpectrum;
constexpr double kPi = npf::kPiD;

Vec3 view(double theta_deg, double phi_deg = 0.0) {
    return npf::spherical_direction(float(theta_deg * kPi / 180.0), float(phi_deg * kPi / 180.0));
}

AnalyticMaterial lambertian(double rho) {
    AnalyticMaterial m;
    m.name = "lambertian";
    m.diffuse = SampledSpectrum::constant(rho);
    return m;
}

// One GGX lobe with F = 1 and weight 1: a white microfacet reflector, albedo at most 1.
AnalyticMaterial white_ggx(float alpha_x, float alpha_y, float rotation = 0.f) {
    AnalyticMaterial m;
    m.name = "white ggx";
    npf::MicrofacetNdf ndf;
    ndf.alpha_x = alpha_x;
    ndf.alpha_y = alpha_y;
    ndf.rotation = rotation;
    m.specular.push_back(npf::SpecularLobe{ndf, npf::Fresnel::one(), SampledSpectrum::constant(1.0)});
    return m;
}

ChannelQuery at_550(const Brdf& b) { return b.query(Channels::spectral({550.f})); }

// The albedo as an integral over the half vector h, independent of any sampler: wo = reflect(wi,
// h), d(wo) = 4 (wi.h) d(h); midpoint rule in phi_h and in v with tan(theta_h) = alpha v / (1 - v),
// which puts half the nodes inside the lobe's core whatever its width.
double half_vector_quadrature(const Brdf& b, const ChannelQuery& q, const Vec3& wi, double alpha, int nv, int nphi) {
    double sum = 0.0;
    for (int i = 0; i < nv; ++i) {
        const double v = (i + 0.5) / nv, t = alpha * v / (1.0 - v);
        const double theta = std::atan(t), dtheta = alpha / ((1.0 - v) * (1.0 - v) * (1.0 + t * t)) / nv;
        for (int j = 0; j < nphi; ++j) {
            const double phi = 2.0 * kPi * (j + 0.5) / nphi;
            const double hx = std::sin(theta) * std::cos(phi), hy = std::sin(theta) * std::sin(phi),
                         hz = std::cos(theta);
            const double c = wi.x * hx + wi.y * hy + wi.z * hz;
            if (c <= 0.0) continue;
            const Vec3 wo(float(2 * c * hx - wi.x), float(2 * c * hy - wi.y), float(2 * c * hz - wi.z));
            if (!(wo.z > 0.f)) continue;
            float f = 0.f;
            b.eval_cos(wi, npf::normalize(wo), q, &f);
            sum += double(f) * 4.0 * c * std::sin(theta) * dtheta * (2.0 * kPi / nphi);
        }
    }
    return sum;
}

// A Lambertian material whose sampler only reaches a cone of 30 degrees around the normal
// (uniform in it; pdf exact, 0 outside): a sampler-only estimate would find sin^2(30) = 1/4 of
// the energy.
class ConeSampledLambertian final : public Brdf {
public:
    explicit ConeSampledLambertian(double rho) : m_inner(lambertian(rho)) {}
    const npf::BrdfInfo& info() const override { return m_inner.info(); }
    ChannelQuery query(const Channels& requested) const override { return m_inner.query(requested); }
    void eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& q, float* out) const override {
        m_inner.eval_cos(wi, wo, q, out);
    }
    float pdf(const Vec3& wi, const Vec3& wo) const override {
        return wi.z > 0.f && wo.z >= kCosCone ? float(1.0 / (2.0 * kPi * (1.0 - kCosCone))) : 0.f;
    }
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& q, npf::BrdfSample& s, float* weight) const override {
        if (!(wi.z > 0.f)) return false;
        const double z = 1.0 - u.x * (1.0 - kCosCone), r = std::sqrt(std::max(0.0, 1.0 - z * z));
        s.wo = Vec3(float(r * std::cos(2 * kPi * u.y)), float(r * std::sin(2 * kPi * u.y)), float(z));
        s.pdf = pdf(wi, s.wo);
        if (weight) {
            eval_cos(wi, s.wo, q, weight);
            for (std::size_t c = 0; c < q.size(); ++c) weight[c] /= s.pdf;
        }
        return s.pdf > 0.f;
    }

private:
    static constexpr double kCosCone = 0.86602540378443865;  // cos 30 degrees
    AnalyticBrdf m_inner;
};

TEST(DirectionalAlbedo, AnalyticLambertianIsItsAlbedoExactly) {
    const AnalyticBrdf b(lambertian(0.5));
    const ChannelQuery q = b.query(Channels::spectral({450.f, 550.f, 650.f}));
    for (double theta : npf::default_albedo_thetas()) {
        std::vector<double> se;
        const std::vector<double> a = npf::directional_albedo(b, view(theta, 30.0), q, {}, &se);
        ASSERT_EQ(a.size(), 3u);
        for (std::size_t c = 0; c < 3; ++c) {
            EXPECT_NEAR(a[c], 0.5, 1e-6) << "theta " << theta;
            EXPECT_LT(se[c], 1e-6) << "theta " << theta;
        }
    }
}

// An NPF model stores rho_d as a BRDF value: its diffuse albedo is pi rho_d.
TEST(DirectionalAlbedo, NpfLambertianIsPiRhoD) {
    npf::testing::MicrofacetSpec spec;
    spec.rho_d = 0.2;
    spec.rho_s = 0.0;
    const npf::NpfBrdf b(npf::compress_factors(npf::testing::make_microfacet_factors(spec), npf::CompressionOptions()));
    const ChannelQuery q = b.native_query();
    DirectionalAlbedoOptions o;
    o.samples = 32;
    for (double theta : {0.0, 45.0, 89.0}) {
        const std::vector<double> a = npf::directional_albedo(b, view(theta), q, o);
        for (std::size_t c = 0; c < a.size(); ++c)
            EXPECT_NEAR(a[c], kPi * b.model().rho_d[c], 1e-5 * kPi * b.model().rho_d[c]) << "theta " << theta;
    }
}

TEST(DirectionalAlbedo, SamplerThatMissesEnergyCannotHideIt) {
    const ConeSampledLambertian b(0.5);
    const ChannelQuery q = at_550(b);
    // The material's sampler alone: a quarter of the energy.
    double sampler_only = 0.0;
    const int n = 64;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            npf::BrdfSample s;
            float w = 0.f;
            if (b.sample(view(40.0), Vec2{(i + 0.5f) / n, (j + 0.5f) / n}, q, s, &w)) sampler_only += w;
        }
    }
    EXPECT_NEAR(sampler_only / (n * n), 0.125, 1e-3);
    for (double theta : {0.0, 40.0, 89.0}) {
        std::vector<double> se;
        const double a = npf::directional_albedo(b, view(theta), q, {}, &se)[0];
        EXPECT_NEAR(a, 0.5, 2e-3) << "theta " << theta;
        EXPECT_LE(std::fabs(a - 0.5), 4.0 * se[0]) << "theta " << theta;
    }
}

// Mirror-sharp (alpha 0.01) to rough (0.5) white GGX against the half-vector quadrature: within
// 0.3 % and 4 standard errors at every view angle, 89 degrees included, and never above 1.
TEST(DirectionalAlbedo, MicrofacetLobesMatchQuadratureUpToGrazing) {
    for (float alpha : {0.01f, 0.1f, 0.5f}) {
        const AnalyticBrdf b(white_ggx(alpha, alpha));
        const ChannelQuery q = at_550(b);
        for (double theta : {0.0, 60.0, 85.0, 89.0}) {
            const Vec3 wi = view(theta, 20.0);
            const double reference = half_vector_quadrature(b, q, wi, alpha, 1500, 192);
            std::vector<double> se;
            const double a = npf::directional_albedo(b, wi, q, {}, &se)[0];
            EXPECT_NEAR(a, reference, 3e-3 * reference) << "alpha " << alpha << " theta " << theta;
            EXPECT_LE(std::fabs(a - reference), 4.0 * se[0] + 1e-5) << "alpha " << alpha << " theta " << theta;
            EXPECT_GT(se[0], 0.0);
            EXPECT_LE(a, 1.0 + 3.0 * se[0]) << "alpha " << alpha << " theta " << theta;
            EXPECT_GT(a, 0.5) << "alpha " << alpha << " theta " << theta;
        }
    }
}

// The whole default table of a mirror-like lobe (alpha 0.01): at most 1, little lost (Smith
// masking and the tail below the horizon), and a standard error that makes 1 % visible.
TEST(DirectionalAlbedo, DefaultTableIsBoundedForASharpLobe) {
    const AnalyticBrdf b(white_ggx(0.01f, 0.01f));
    AlbedoTableOptions o;
    const std::vector<AlbedoRow> rows = npf::directional_albedo_table(b, at_550(b), o);
    ASSERT_EQ(rows.size(), npf::default_albedo_thetas().size());
    for (const AlbedoRow& row : rows) {
        EXPECT_LE(row.albedo[0], 1.0 + 3.0 * row.standard_error[0]) << "theta " << row.theta_deg;
        EXPECT_GT(row.albedo[0], 0.9) << "theta " << row.theta_deg;  // little is lost at alpha 0.01
        EXPECT_LT(row.standard_error[0], 1.5e-3) << "theta " << row.theta_deg;
    }
}

TEST(DirectionalAlbedo, TableRowsAndAzimuths) {
    const AnalyticBrdf iso(white_ggx(0.3f, 0.3f));
    AlbedoTableOptions o;
    o.estimator.samples = 8;
    std::vector<AlbedoRow> rows = npf::directional_albedo_table(iso, at_550(iso), o);
    ASSERT_EQ(rows.size(), 12u);
    for (std::size_t k = 0; k < rows.size(); ++k) {
        EXPECT_EQ(rows[k].theta_deg, npf::default_albedo_thetas()[k]);
        EXPECT_EQ(rows[k].phi_deg, 0.0);
        EXPECT_EQ(rows[k].albedo.size(), 1u);
        EXPECT_EQ(rows[k].standard_error.size(), 1u);
    }

    // Anisotropic: four azimuths per view angle, theta outermost.
    const AnalyticBrdf aniso(white_ggx(0.05f, 0.4f));
    ASSERT_FALSE(aniso.info().isotropic);
    o.theta_deg = {0.0, 70.0};
    rows = npf::directional_albedo_table(aniso, at_550(aniso), o);
    ASSERT_EQ(rows.size(), 8u);
    const double phis[] = {0.0, 90.0, 180.0, 270.0};
    for (std::size_t k = 0; k < rows.size(); ++k) {
        EXPECT_EQ(rows[k].theta_deg, k < 4 ? 0.0 : 70.0);
        EXPECT_EQ(rows[k].phi_deg, phis[k % 4]);
    }

    // Explicit azimuths are taken as given.
    o.phi_deg = {15.0};
    rows = npf::directional_albedo_table(aniso, at_550(aniso), o);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[1].phi_deg, 15.0);
}

// A quarter turn of the lobe moves the albedo from phi to phi + 90: the azimuth reaches wi.
TEST(DirectionalAlbedo, AnisotropicLobeFollowsItsRotation) {
    const AnalyticBrdf a(white_ggx(0.05f, 0.5f)), b(white_ggx(0.05f, 0.5f, float(kPi / 2)));
    DirectionalAlbedoOptions o;
    o.samples = 64;
    for (double theta : {60.0, 85.0}) {
        std::vector<double> se_a, se_b;
        const double along = npf::directional_albedo(a, view(theta, 0.0), at_550(a), o, &se_a)[0];
        const double turned = npf::directional_albedo(b, view(theta, 90.0), at_550(b), o, &se_b)[0];
        const double across = npf::directional_albedo(a, view(theta, 90.0), at_550(a), o)[0];
        EXPECT_NEAR(along, turned, 4.0 * std::hypot(se_a[0], se_b[0])) << "theta " << theta;
        EXPECT_GT(std::fabs(along - across), 0.01) << "theta " << theta;  // the azimuth matters
    }
}

// Same numbers to the bit: twice, and on 1 or 2 threads; for a tabulated (RGL) material with its
// own sampler too.
TEST(DirectionalAlbedo, BitIdenticalRunsAndThreadCounts) {
    npf::testing::SyntheticRglSpec spec;
    spec.phi_count = 6;  // anisotropic
    const std::string dir = npf::testing::temporary_folder("albedo");
    const std::unique_ptr<Brdf> rgl = npf::open_material(npf::testing::write_synthetic_rgl(spec, dir + "/aniso.bsdf"));
    const AnalyticBrdf analytic(white_ggx(0.02f, 0.2f, 0.4f));
    for (const Brdf* b : {static_cast<const Brdf*>(rgl.get()), static_cast<const Brdf*>(&analytic)}) {
        const ChannelQuery q = b == rgl.get() ? b->native_query() : at_550(*b);
        AlbedoTableOptions o;
        o.estimator.samples = 24;
        o.threads = 1;
        const std::vector<AlbedoRow> one = npf::directional_albedo_table(*b, q, o);
        o.threads = 2;
        const std::vector<AlbedoRow> two = npf::directional_albedo_table(*b, q, o);
        const std::vector<AlbedoRow> again = npf::directional_albedo_table(*b, q, o);
        ASSERT_EQ(one.size(), 48u);
        ASSERT_EQ(two.size(), one.size());
        ASSERT_EQ(again.size(), one.size());
        for (std::size_t k = 0; k < one.size(); ++k) {
            EXPECT_EQ(one[k].albedo, two[k].albedo) << "row " << k;  // exact comparison
            EXPECT_EQ(one[k].standard_error, two[k].standard_error) << "row " << k;
            EXPECT_EQ(two[k].albedo, again[k].albedo) << "row " << k;
            EXPECT_EQ(one[k].theta_deg, two[k].theta_deg);
            EXPECT_EQ(one[k].phi_deg, two[k].phi_deg);
        }
        // ... and equal to the single-direction function.
        DirectionalAlbedoOptions single;
        single.samples = 24;
        EXPECT_EQ(npf::directional_albedo(*b, view(one[21].theta_deg, one[21].phi_deg), q, single), one[21].albedo);
    }
}

TEST(DirectionalAlbedo, RefusesDirectionsAtOrBelowTheHorizonAndBadOptions) {
    const AnalyticBrdf b(lambertian(0.5));
    const ChannelQuery q = at_550(b);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (const Vec3& wi : {Vec3(1.f, 0.f, 0.f), Vec3(0.f, 0.6f, -0.8f), Vec3(0.f, 0.f, -1.f), Vec3(nan, 0.f, 1.f)}) {
        const std::string msg = npf::testing::error_of([&] { npf::directional_albedo(b, wi, q); });
        EXPECT_NE(msg.find("above the horizon"), std::string::npos) << msg;
    }
    DirectionalAlbedoOptions o;
    o.samples = 1;
    EXPECT_NE(npf::testing::error_of([&] { npf::directional_albedo(b, view(10.0), q, o); }).find("samples"),
              std::string::npos);

    AlbedoTableOptions t;
    t.estimator.samples = 4;
    for (double bad : {90.0, -1.0, 120.0, std::nan("")}) {
        t.theta_deg = {0.0, bad};
        const std::string msg = npf::testing::error_of([&] { npf::directional_albedo_table(b, q, t); });
        EXPECT_NE(msg.find("outside [0, 90)"), std::string::npos) << msg;
    }
    t.theta_deg = {};
    EXPECT_NE(npf::testing::error_of([&] { npf::directional_albedo_table(b, q, t); }).find("no view angles"),
              std::string::npos);
    t.theta_deg = {10.0};
    t.phi_deg = {std::numeric_limits<double>::infinity()};
    EXPECT_NE(npf::testing::error_of([&] { npf::directional_albedo_table(b, q, t); }).find("azimuth"),
              std::string::npos);
}

}  // namespace
