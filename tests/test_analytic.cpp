// Analytic materials: microfacet NDFs (normalisation, projected area, masking, sampling),
// Fresnel terms (conductor, dielectric, Schlick, thin-film Airy), and AnalyticBrdf (formula
// properties, RGB projection, sampling against pdf by chi-square, robustness).
#include "chi2.h"
#include "synthetic_rgl.h"

#include <npf/color/spectrum.h>
#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/materials/analytic/fresnel.h>
#include <npf/materials/analytic/microfacet.h>
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

using npf::AnalyticBrdf;
using npf::AnalyticMaterial;
using npf::ChannelQuery;
using npf::Channels;
using npf::Fresnel;
using npf::MicrofacetDistribution;
using npf::MicrofacetNdf;
using npf::SpecularLobe;
using npf::Vec2;
using npf::Vec3;
using npf::color::SampledSpectrum;
using npf::testing::Chi2Options;
using npf::testing::Chi2Result;
using npf::testing::Pcg32;

constexpr double kPi = npf::kPiD;

SampledSpectrum constant(double v) { return SampledSpectrum::constant(v); }
SampledSpectrum ramp(double a, double b) { return SampledSpectrum({400.0, 700.0}, {a, b}); }

MicrofacetNdf ndf(MicrofacetDistribution type, float ax, float ay, float rot = 0.f) {
    MicrofacetNdf n;
    n.type = type;
    n.alpha_x = ax;
    n.alpha_y = ay;
    n.rotation = rot;
    return n;
}

std::string describe(const MicrofacetNdf& n) {
    return std::string(n.type == MicrofacetDistribution::Ggx ? "GGX" : "Beckmann") + " " +
           std::to_string(n.alpha_x) + " x " + std::to_string(n.alpha_y) + " rot " + std::to_string(n.rotation);
}

std::string str(const Vec3& v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

Vec3 uniform_hemisphere(Pcg32& rng) {
    const float z = std::max(1e-4f, rng.next_float());
    const float r = std::sqrt(std::max(0.f, 1.f - z * z));
    const float phi = float(2.0 * kPi) * rng.next_float();
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// Midpoint quadrature over the upper hemisphere in (theta = pi/2 v^2, phi): the square-root
// map puts most nodes near the normal, where sharp lobes live.
template <typename F>
double hemisphere_integral(F f, int nv = 400, int nphi = 256) {
    double sum = 0.0;
    for (int i = 0; i < nv; ++i) {
        const double v = (i + 0.5) / nv;
        const double theta = 0.5 * kPi * v * v;
        const double w_theta = kPi * v / nv * std::sin(theta);  // dtheta sin(theta)
        for (int j = 0; j < nphi; ++j) {
            const double phi = 2.0 * kPi * (j + 0.5) / nphi;
            const Vec3 m(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                         float(std::cos(theta)));
            sum += f(m, std::cos(theta)) * w_theta * (2.0 * kPi / nphi);
        }
    }
    return sum;
}

std::vector<MicrofacetNdf> ndf_cases() {
    std::vector<MicrofacetNdf> out;
    for (MicrofacetDistribution t : {MicrofacetDistribution::Ggx, MicrofacetDistribution::Beckmann}) {
        for (float a : {0.05f, 0.1f, 0.3f, 0.6f, 1.0f}) out.push_back(ndf(t, a, a));
        out.push_back(ndf(t, 0.05f, 0.3f, 0.4f));
        out.push_back(ndf(t, 0.5f, 0.08f, -1.1f));
        out.push_back(ndf(t, 1.0f, 0.2f, 2.0f));
    }
    return out;
}

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

// ==== Fresnel ==============================================================================

double bare_conductor(double c, double eta, double k) {
    return Fresnel::conductor(constant(eta), constant(k)).eval(c, 550.0);
}

TEST(AnalyticFresnel, ConductorAtNormalIncidence) {
    for (auto nk : {std::pair<double, double>{0.2, 3.0}, {1.1, 2.5}, {2.5, 0.5}, {1.5, 0.0}, {0.05, 4.2}}) {
        const double n = nk.first, k = nk.second;
        const double want = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
        EXPECT_NEAR(bare_conductor(1.0, n, k), want, 1e-12) << n << " + " << k << "i";
    }
}

TEST(AnalyticFresnel, ConductorTendsToOneAtGrazing) {
    for (auto nk : {std::pair<double, double>{0.2, 3.0}, {1.1, 2.5}, {2.5, 0.5}}) {
        EXPECT_DOUBLE_EQ(bare_conductor(0.0, nk.first, nk.second), 1.0);
        EXPECT_GT(bare_conductor(1e-4, nk.first, nk.second), 0.999);
        // and it approaches 1 monotonically over the last degrees
        EXPECT_GT(bare_conductor(0.01, nk.first, nk.second), bare_conductor(0.1, nk.first, nk.second));
    }
}

// The conductor closed form with k = 0 and the dielectric formula are separate code paths.
TEST(AnalyticFresnel, ConductorWithoutAbsorptionIsDielectric) {
    for (double eta : {1.2, 1.5, 2.4}) {
        const Fresnel d = Fresnel::dielectric(constant(eta));
        for (int i = 0; i <= 50; ++i) {
            const double c = i / 50.0;
            EXPECT_NEAR(bare_conductor(c, eta, 0.0), d.eval(c, 500.0), 1e-12) << "eta " << eta << " cos " << c;
        }
    }
}

TEST(AnalyticFresnel, Dielectric) {
    const Fresnel d = Fresnel::dielectric(constant(1.5));
    EXPECT_NEAR(d.eval(1.0, 550.0), 0.04, 1e-12);
    EXPECT_DOUBLE_EQ(d.eval(0.0, 550.0), 1.0);
    // Brewster angle: p vanishes, R = rs^2 / 2.
    const double tb = std::atan(1.5), c = std::cos(tb), ct = std::cos(std::asin(std::sin(tb) / 1.5));
    const double rs = (c - 1.5 * ct) / (c + 1.5 * ct);
    EXPECT_NEAR(d.eval(c, 550.0), 0.5 * rs * rs, 1e-12);
    // eta < 1 (into a rarer medium): total reflection past the critical angle.
    const Fresnel rare = Fresnel::dielectric(constant(0.8));
    EXPECT_DOUBLE_EQ(rare.eval(std::cos(std::asin(0.8) + 0.01), 550.0), 1.0);
    EXPECT_LT(rare.eval(1.0, 550.0), 0.02);
}

TEST(AnalyticFresnel, SchlickUsesF0Spectrum) {
    const Fresnel s = Fresnel::schlick(ramp(0.2, 0.9));
    EXPECT_NEAR(s.eval(1.0, 400.0), 0.2, 1e-12);
    EXPECT_NEAR(s.eval(1.0, 700.0), 0.9, 1e-12);
    EXPECT_NEAR(s.eval(1.0, 550.0), 0.55, 1e-12);
    EXPECT_DOUBLE_EQ(s.eval(0.0, 550.0), 1.0);
    EXPECT_NEAR(s.eval(0.5, 400.0), 0.2 + 0.8 / 32.0, 1e-12);
}

TEST(AnalyticFresnel, ThinFilmOfZeroThicknessIsTheBareBase) {
    struct Base {
        double eta, k;
    };
    for (Base b : {Base{0.27, 3.4}, Base{0.18, 2.9}, Base{1.5, 0.0}, Base{2.4, 0.0}, Base{1.2, 0.1}}) {
        for (double film : {0.8, 1.2, 1.45, 2.0, 3.0}) {
            const Fresnel tf = Fresnel::thin_film(0.0, constant(film), constant(b.eta), constant(b.k));
            for (int i = 0; i <= 40; ++i) {
                const double c = i / 40.0;
                EXPECT_NEAR(tf.eval(c, 550.0), bare_conductor(c, b.eta, b.k), 1e-6)
                    << "base " << b.eta << "+" << b.k << "i film " << film << " cos " << c;
            }
        }
    }
}

// Notes sec. 3: a quarter-wave film of index sqrt(n3) on a dielectric n3 cancels the normal
// reflection at the design wavelength, and only there.
TEST(AnalyticFresnel, ThinFilmQuarterWaveIsAntiReflective) {
    const double n3 = 1.9, n2 = std::sqrt(n3), lambda = 550.0, d = lambda / (4.0 * n2);
    const Fresnel tf = Fresnel::thin_film(d, constant(n2), constant(n3), constant(0.0));
    EXPECT_LT(tf.eval(1.0, lambda), 1e-12);
    const double bare = bare_conductor(1.0, n3, 0.0);
    EXPECT_GT(bare, 0.09);
    EXPECT_GT(tf.eval(1.0, 400.0), 1e-3);
    // A half-wave film is "absent" at normal incidence.
    const Fresnel half = Fresnel::thin_film(2.0 * d, constant(n2), constant(n3), constant(0.0));
    EXPECT_NEAR(half.eval(1.0, lambda), bare, 1e-12);
}

// Belcour & Barla's real-valued form (notes sec. 3), written independently from complex r's.
double belcour_reflectance(double c1, double lambda, double d, double n2, double eta3, double k3) {
    using C = std::complex<double>;
    const double s2 = 1.0 - c1 * c1;
    const double c2 = std::sqrt(1.0 - s2 / (n2 * n2));
    const C n3(eta3, k3);
    C c3 = std::sqrt(1.0 - s2 / (n3 * n3));
    if ((n3 * c3).imag() < 0.0) c3 = -c3;
    const C r12[2] = {(c1 - n2 * c2) / (c1 + n2 * c2), (n2 * c1 - c2) / (n2 * c1 + c2)};
    const C r23[2] = {(n2 * c2 - n3 * c3) / (n2 * c2 + n3 * c3), (n3 * c2 - n2 * c3) / (n3 * c2 + n2 * c3)};
    double sum = 0.0;
    for (int p = 0; p < 2; ++p) {
        const double R12 = std::norm(r12[p]), R23 = std::norm(r23[p]), T121 = 1.0 - R12;
        const double Rs = T121 * T121 * R23 / (1.0 - R12 * R23);
        const double r123 = std::sqrt(R12 * R23);
        const double phi = 2.0 * kPi * (2.0 * n2 * d * c2) / lambda + (kPi - std::arg(r12[p])) + std::arg(r23[p]);
        sum += R12 + Rs + 2.0 * (Rs - T121) * (r123 * std::cos(phi) - r123 * r123) /
                              (1.0 - 2.0 * r123 * std::cos(phi) + r123 * r123);
    }
    return 0.5 * sum;
}

TEST(AnalyticFresnel, ThinFilmMatchesRealValuedAiryForm) {
    Pcg32 rng(11);
    for (int i = 0; i < 2000; ++i) {
        const double c = 0.02 + 0.98 * rng.next_float();
        const double lambda = 380.0 + 400.0 * rng.next_float();
        const double d = 1000.0 * rng.next_float();
        const double n2 = 1.05 + 1.5 * rng.next_float();
        const bool metal = i % 2 == 0;
        const double eta3 = metal ? 0.1 + 1.5 * rng.next_float() : 1.1 + 1.5 * rng.next_float();
        const double k3 = metal ? 0.5 + 4.0 * rng.next_float() : 0.0;
        const Fresnel tf = Fresnel::thin_film(d, constant(n2), constant(eta3), constant(k3));
        const double got = tf.eval(c, lambda), want = belcour_reflectance(c, lambda, d, n2, eta3, k3);
        ASSERT_NEAR(got, want, 1e-9) << "cos " << c << " lambda " << lambda << " d " << d << " n2 " << n2
                                     << " base " << eta3 << "+" << k3 << "i";
    }
}

TEST(AnalyticFresnel, ValuesStayInUnitInterval) {
    std::vector<Fresnel> fs = {Fresnel::conductor(ramp(0.2, 1.3), ramp(3.5, 2.0)), Fresnel::dielectric(ramp(1.3, 1.7)),
                               Fresnel::dielectric(constant(0.7)), Fresnel::schlick(ramp(0.0, 1.0)), Fresnel::one()};
    for (double d : {0.0, 80.0, 350.0, 2000.0}) {
        fs.push_back(Fresnel::thin_film(d, constant(1.33), ramp(0.2, 1.3), ramp(3.5, 2.0)));
        fs.push_back(Fresnel::thin_film(d, constant(2.2), constant(1.5), constant(0.0)));
        fs.push_back(Fresnel::thin_film(d, constant(0.9), constant(1.5), constant(0.0)));  // evanescent film
    }
    for (const Fresnel& f : fs) {
        for (int i = 0; i <= 200; ++i) {
            for (double lambda : {360.0, 450.0, 555.5, 700.0, 1000.0}) {
                const double c = i / 200.0;
                const double v = f.eval(c, lambda);
                ASSERT_TRUE(v >= 0.0 && v <= 1.0) << "kind " << int(f.kind()) << " cos " << c << " -> " << v;
                EXPECT_EQ(v, f.eval(c, f.coefficients(lambda)));
            }
        }
    }
}

// Fresnel::eval over many wavelengths (the vectorised conductor loop, portable and AVX2) gives
// the one-at-a-time values to the bit, and both follow the complex-amplitude Fresnel equations.
TEST(AnalyticFresnel, ManyWavelengthsGiveTheOneAtATimeBits) {
    // eta 1, k 0 in the middle of the range (no interface), metals, and a weak absorber.
    const SampledSpectrum eta({400.0, 500.0, 550.0, 600.0, 700.0}, {0.2, 1.0, 1.0, 1.0, 2.5});
    const SampledSpectrum k({400.0, 500.0, 550.0, 600.0, 700.0}, {3.5, 0.0, 0.0, 0.0, 0.01});
    const Fresnel f = Fresnel::conductor(eta, k);
    std::vector<Fresnel::Coefficients> coefficients;
    for (int j = 0; j < 37; ++j) coefficients.push_back(f.coefficients(380.0 + 10.0 * j));  // 37: a vector tail
    std::vector<npf::SimdIsa> isas = {npf::SimdIsa::Portable};
    if (npf::simd_isa_supported(npf::SimdIsa::Avx2)) isas.push_back(npf::SimdIsa::Avx2);
    for (npf::SimdIsa isa : isas) {
        const npf::SimdIsaScope scope(isa);
        for (double c : {0.0, 1e-9, 1e-4, 0.01, 0.3, 0.70710678, 0.999, 1.0, -0.5, 1.5}) {
            std::vector<double> many(coefficients.size(), -1.0);
            f.eval(c, coefficients.data(), coefficients.size(), many.data());
            for (std::size_t j = 0; j < coefficients.size(); ++j) {
                const double one = f.eval(c, coefficients[j]);
                EXPECT_EQ(many[j], one) << npf::simd_isa_name(isa) << " cos " << c << " channel " << j;
                const double a = coefficients[j].a, b = coefficients[j].b;
                const double cc = std::min(1.0, std::fabs(c));
                if (a == 1.0 && b == 0.0) {
                    EXPECT_EQ(one, 0.0);
                    continue;
                }
                // Air -> n = a + i b: r_s = (c - n c_t) / (c + n c_t), r_p = (n c - c_t) / (n c + c_t).
                const std::complex<double> n(a, b), ct = std::sqrt(1.0 - (1.0 - cc * cc) / (n * n));
                const double rs = std::norm((cc - n * ct) / (cc + n * ct)), rp = std::norm((n * cc - ct) / (n * cc + ct));
                if (cc > 0.0) {
                    EXPECT_NEAR(one, 0.5 * (rs + rp), 1e-12) << "cos " << c << " n " << a << " + " << b << "i";
                }
            }
        }
    }
}

TEST(AnalyticFresnel, ConductorFromIorFilesCopper) {
    const std::string eta_file = npf::testing::shared_data_file("ior/Cu.eta.spd");
    if (eta_file.empty() || npf::testing::shared_data_file("ior/Cu.k.spd").empty())
        GTEST_SKIP() << "ior/Cu.{eta,k}.spd not found in the shared data folder";
    const std::string dir = eta_file.substr(0, eta_file.rfind('/'));
    const Fresnel cu = npf::conductor_from_ior_files(dir, "Cu");
    EXPECT_EQ(cu.kind(), Fresnel::Kind::Conductor);
    const SampledSpectrum eta = npf::color::read_spd(dir + "/Cu.eta.spd");
    const SampledSpectrum k = npf::color::read_spd(dir + "/Cu.k.spd");
    for (double lambda : {400.0, 500.0, 600.0, 700.0}) {
        const double n = eta(lambda), kk = k(lambda);
        EXPECT_NEAR(cu.eval(1.0, lambda), ((n - 1) * (n - 1) + kk * kk) / ((n + 1) * (n + 1) + kk * kk), 1e-12);
    }
    // Copper: reddish, about 0.95 in the red and 0.5-0.6 in the blue.
    EXPECT_GT(cu.eval(1.0, 700.0), 0.9);
    EXPECT_LT(cu.eval(1.0, 450.0), 0.7);
    EXPECT_THROW(npf::conductor_from_ior_files(dir, "Unobtainium"), npf::Error);
}

TEST(AnalyticFresnel, FactoriesRejectBadInput) {
    EXPECT_THROW(Fresnel::conductor(SampledSpectrum(), constant(1.0)), npf::Error);
    EXPECT_THROW(Fresnel::dielectric(constant(-1.0)), npf::Error);
    EXPECT_THROW(Fresnel::schlick(constant(1.5)), npf::Error);
    EXPECT_THROW(Fresnel::thin_film(-1.0, constant(1.3), constant(1.5), constant(0.0)), npf::Error);
    EXPECT_THROW(Fresnel::thin_film(NAN, constant(1.3), constant(1.5), constant(0.0)), npf::Error);
}

// ==== AnalyticBrdf =========================================================================

ChannelQuery spectral_query(const AnalyticBrdf& b, std::vector<float> wl) { return b.query(Channels::spectral(wl)); }

AnalyticMaterial one_lobe(MicrofacetNdf n, Fresnel f = Fresnel::one(), SampledSpectrum w = constant(1.0)) {
    AnalyticMaterial m;
    m.name = "test lobe";
    m.specular.push_back(SpecularLobe{n, std::move(f), std::move(w)});
    return m;
}

Fresnel gold_like() { return Fresnel::conductor(ramp(1.5, 0.15), ramp(1.9, 3.9)); }

AnalyticMaterial coated_plastic() {
    AnalyticMaterial m = one_lobe(ndf(MicrofacetDistribution::Ggx, 0.15f, 0.15f), Fresnel::dielectric(constant(1.5)));
    m.name = "coated plastic";
    m.diffuse = ramp(0.6, 0.1);
    return m;
}

AnalyticMaterial two_lobes() {
    AnalyticMaterial m = one_lobe(ndf(MicrofacetDistribution::Ggx, 0.08f, 0.08f), gold_like());
    m.name = "two lobes";
    m.specular.push_back(SpecularLobe{ndf(MicrofacetDistribution::Beckmann, 0.6f, 0.2f, 1.0f),
                                      Fresnel::schlick(constant(0.3)), ramp(0.5, 1.0)});
    return m;
}

AnalyticMaterial retro_and_sheen() {
    AnalyticMaterial m;
    m.name = "retro and sheen";
    m.retroreflection = ramp(0.3, 0.8);
    m.retro_exponent = 20.f;
    m.sheen = ramp(0.9, 0.4);
    m.sheen_roughness = 0.35f;
    m.diffuse = constant(0.1);
    return m;
}

// Every kind of term, sharp and rotated, for the robustness and reciprocity tests.
AnalyticMaterial everything(float alpha) {
    AnalyticMaterial m;
    m.name = "everything";
    m.specular.push_back(SpecularLobe{ndf(MicrofacetDistribution::Ggx, alpha, alpha), gold_like(), constant(1.0)});
    m.specular.push_back(SpecularLobe{ndf(MicrofacetDistribution::Beckmann, alpha, 0.2f, 0.7f),
                                      Fresnel::thin_film(300.0, constant(1.4), ramp(0.3, 1.2), ramp(3.0, 2.0)),
                                      ramp(0.2, 0.8)});
    m.specular.push_back(SpecularLobe{ndf(MicrofacetDistribution::Ggx, 0.3f, alpha, -1.2f),
                                      Fresnel::dielectric(constant(1.5)), constant(1.0)});
    m.diffuse = ramp(0.5, 0.2);
    m.retroreflection = constant(0.4);
    m.retro_exponent = 1000.f;
    m.sheen = constant(0.5);
    m.sheen_roughness = 0.1f;
    return m;
}

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
