// Fresnel terms of the analytic materials: conductor, dielectric, Schlick and the thin-film
// Airy form, against closed forms and the shipped index files.

#include "analytic_materials.h"
#include "chi2.h"
#include "synthetic_rgl.h"

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

}  // namespace
