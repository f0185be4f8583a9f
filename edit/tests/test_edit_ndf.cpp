// NDF edits by a linear transform (issue 7, docs/editing.md): the identity changes nothing, the
// projected area stays 1, stretches, rotations and roughness scales of a GGX material give the
// GGX material with the transformed roughness (D and Smith's G) to the grid's interpolation
// error, a stretch and its inverse come back to that error, and D and G are compressed again at
// the input's rank.
#include "model_equality.h"
#include "npf_test_factors.h"

#include <npf/fit/spectral_compression.h>
#include <npf/core/error.h>
#include <npf/edit/ndf_transform.h>
#include <npf/shading/npf_model.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using npf::NpfModel, npf::edit::Mat3, npf::testing::MicrofacetSpec;
constexpr double kPi = npf::kPiD;

NpfModel microfacet(double ax, double ay, bool anisotropic, bool spectral = false, int d_theta = 32) {
    MicrofacetSpec s;
    s.alpha_x = ax;
    s.alpha_y = ay;
    s.rho_d = 0.05;
    s.rho_s = 0.1;
    s.spectral = spectral;
    s.channels = spectral ? 6 : 3;
    s.set_grid(d_theta, anisotropic ? 2 * d_theta : 1, 32, 32, anisotropic ? 64 : 1);
    return npf::compress_factors(npf::testing::make_microfacet_factors(s), npf::CompressionOptions());
}

double ggx(double theta, double phi, double ax, double ay) {
    const double c2 = std::cos(theta) * std::cos(theta), t2 = std::tan(theta) * std::tan(theta);
    const double e = t2 * (std::cos(phi) * std::cos(phi) / (ax * ax) + std::sin(phi) * std::sin(phi) / (ay * ay));
    return 1.0 / (kPi * ax * ay * c2 * c2 * (1.0 + e) * (1.0 + e));
}

double smith_g1(double theta, double phi, double ax, double ay) {
    const double t2 = std::tan(theta) * std::tan(theta);
    const double a2 = std::cos(phi) * std::cos(phi) * ax * ax + std::sin(phi) * std::sin(phi) * ay * ay;
    return 1.0 / (1.0 + 0.5 * (std::sqrt(1.0 + a2 * t2) - 1.0));
}

double d_theta_at(const NpfModel& m, int i) {
    const double u = (i + 0.5) / m.d_theta;
    return 0.5 * kPi * u * u;
}
double d_phi_at(const NpfModel& m, int j) { return m.d_phi == 1 ? 0.0 : 2.0 * kPi * (j + 0.5) / m.d_phi; }

// Relative RMS of channel c's D table against `want`, weighted by each cell's share of the
// projected area (cos sin u du dphi): the error where the lobe's energy is.
template <typename Want>
double d_error(const NpfModel& m, std::size_t c, Want want) {
    double num = 0.0, den = 0.0;
    for (int i = 0; i < m.d_theta; ++i) {
        const double th = d_theta_at(m, i), u = (i + 0.5) / m.d_theta, w = std::cos(th) * std::sin(th) * u;
        for (int j = 0; j < m.d_phi; ++j) {
            const double got = std::max(0.0, m.D.at(c, std::size_t(i) * std::size_t(m.d_phi) + std::size_t(j)));
            const double x = want(th, d_phi_at(m, j));
            num += w * (got - x) * (got - x);
            den += w * x * x;
        }
    }
    return std::sqrt(num / den);
}

// Largest absolute difference of G (theta < 75 degrees) against `want`.
template <typename Want>
double g_error(const NpfModel& m, std::size_t c, Want want) {
    double worst = 0.0;
    for (int i = 0; i < m.g_theta; ++i) {
        const double th = 0.5 * kPi * (i + 0.5) / m.g_theta;
        if (th > 75.0 * kPi / 180.0) break;
        for (int j = 0; j < m.g_phi; ++j) {
            const double ph = m.g_phi == 1 ? 0.0 : 2.0 * kPi * (j + 0.5) / m.g_phi;
            const double got = m.G.at(c, std::size_t(i) * std::size_t(m.g_phi) + std::size_t(j));
            worst = std::max(worst, std::fabs(got - want(th, ph)));
        }
    }
    return worst;
}

void expect_bit_identical(const NpfModel& a, const NpfModel& b) {
    EXPECT_EQ(a.d_theta, b.d_theta);
    EXPECT_EQ(a.d_phi, b.d_phi);
    EXPECT_EQ(a.g_phi, b.g_phi);
    npf::testing::expect_same_factors(a, b);
    EXPECT_EQ(a.D.singular_values, b.D.singular_values);
}

TEST(EditNdf, IdentityFormsChangeNothing) {
    for (bool aniso : {false, true}) {
        const NpfModel m = microfacet(0.2, 0.4, aniso);
        Mat3 twice;
        for (double& v : twice.m) v *= 2.0;
        for (const Mat3& t : {Mat3::identity(), twice, npf::edit::stretch_matrix(1, 1), npf::edit::rotation_matrix(0),
                              npf::edit::roughness_matrix(1)}) {
            npf::edit::EditRecord r;
            const NpfModel out = npf::edit::transform_ndf(m, t, {}, &r);
            expect_bit_identical(out, m);
            EXPECT_NE(r.summary.find("identity"), std::string::npos) << r.summary;
        }
    }
    // Rotations and reflections of an isotropic material change nothing either.
    const NpfModel iso = microfacet(0.3, 0.3, false);
    expect_bit_identical(npf::edit::transform_ndf(iso, npf::edit::rotation_matrix(37)), iso);
}

// A full turn is not exactly the identity in floating point, so it goes through the whole
// resampling and re-compression: the model must come back to float precision.
TEST(EditNdf, FullTurnThroughTheResamplingReturnsTheModel) {
    const NpfModel m = microfacet(0.15, 0.45, true, true);
    const NpfModel out = npf::edit::transform_ndf(m, npf::edit::rotation_matrix(360.0));
    ASSERT_EQ(out.d_phi, m.d_phi);
    // D is renormalised to projected area 1 on the grid and the input's own area (here the
    // analytic GGX's, 1 - 9e-5 on this grid) moves into rho_s: compare the products.
    const std::vector<double> area = npf::edit::projected_area(m);
    double worst = 0.0;
    for (std::size_t c = 0; c < m.channel_count(); ++c) {
        EXPECT_NEAR(double(out.rho_s[c]) / m.rho_s[c], area[c], 1e-6);
        for (std::size_t k = 0; k < m.D.cells; ++k) {
            const double a = m.D.at(c, k) / area[c], b = out.D.at(c, k);
            worst = std::max(worst, std::fabs(a - b) / std::max(1e-3, std::fabs(a)));
        }
        for (std::size_t k = 0; k < m.G.cells; ++k) worst = std::max(worst, std::fabs(m.G.at(c, k) - out.G.at(c, k)));
    }
    // And the BRDF itself.
    double worst_f = 0.0;
    for (int i = 0; i < 200; ++i) {
        const npf::Vec3 wi = npf::spherical_direction(float(1.4 * ((i * 37) % 100) / 100.0), float(0.1 * i));
        const npf::Vec3 wo = npf::spherical_direction(float(1.4 * ((i * 53) % 100) / 100.0), float(2.0 + 0.17 * i));
        for (std::size_t c = 0; c < m.channel_count(); ++c) {
            const double a = m.eval(c, wi, wo), b = out.eval(c, wi, wo);
            worst_f = std::max(worst_f, std::fabs(a - b) / std::max(1e-3, std::fabs(a)));
        }
    }
    std::printf("[ measured ] full turn: largest relative change of D, G %.3g; of f_r at 200 pairs %.3g\n", worst, worst_f);
    EXPECT_LT(worst, 1e-5);
    EXPECT_LT(worst_f, 1e-5);
}

TEST(EditNdf, ProjectedAreaStaysOne) {
    const std::vector<std::pair<const char*, Mat3>> cases = {
        {"stretch tangent 2", npf::edit::stretch_matrix(2, 1)},
        {"stretch bitangent 0.5", npf::edit::stretch_matrix(1, 0.5)},
        {"rotate 30", npf::edit::rotation_matrix(30)},
        {"sharpen 2", npf::edit::roughness_matrix(0.5)},
        {"blur 2", npf::edit::roughness_matrix(2)},
        {"skew", Mat3{{1.7, 0.4, 0, -0.2, 0.6, 0, 0, 0, 1}}},
    };
    double worst = 0.0;
    for (bool aniso : {false, true}) {
        const NpfModel m = microfacet(0.25, aniso ? 0.5 : 0.25, aniso, true);
        for (const auto& [name, t] : cases) {
            SCOPED_TRACE(name);
            npf::edit::EditRecord r;
            const NpfModel out = npf::edit::transform_ndf(m, t, {}, &r);
            const std::vector<double> area = npf::edit::projected_area(out);
            for (double a : area) {
                EXPECT_NEAR(a, 1.0, 1e-3);
                // (A rotation of the isotropic input returns it unchanged, with its own area.)
                if (!r.summary.empty() && r.summary.find("nothing changed") == std::string::npos) {
                    worst = std::max(worst, std::fabs(a - 1.0));
                }
            }
            // The BRDF's scale is kept: rho_s times the input's own area (1 here).
            const std::vector<double> area_in = npf::edit::projected_area(m);
            for (std::size_t c = 0; c < m.channel_count(); ++c) {
                EXPECT_NEAR(double(out.rho_s[c]) / m.rho_s[c], area_in[c], 2e-3);
            }
            std::printf("[ measured ] %s, %s: %s\n", aniso ? "anisotropic" : "isotropic", name, r.summary.c_str());
        }
    }
    std::printf("[ measured ] projected area after the edits: 1 to %.2g\n", worst);
    EXPECT_LT(worst, 1e-6);
}

TEST(EditNdf, StretchOfGgxIsGgxWithStretchedRoughness) {
    const double ax = 0.2, ay = 0.2;
    const NpfModel m = microfacet(ax, ay, false, false, 64);
    const NpfModel out = npf::edit::transform_ndf(m, npf::edit::stretch_matrix(2.0, 1.0));
    ASSERT_EQ(out.d_phi, 128);  // isotropic became anisotropic: twice the theta cells
    ASSERT_EQ(out.g_phi, 64);
    const double ed = d_error(out, 0, [&](double t, double p) { return ggx(t, p, 2 * ax, ay); });
    const double eg = g_error(out, 0, [&](double t, double p) { return smith_g1(t, p, 2 * ax, ay); });
    // The reference: the same grid's tabulation of the input against the analytic input.
    const double ed0 = d_error(m, 0, [&](double t, double p) { return ggx(t, p, ax, ay); });
    std::printf("[ measured ] GGX 0.2 stretched x2 along the tangent: D rel. RMS %.4f (input's tabulation %.2g), "
                "G max abs %.4f against Smith of GGX (0.4, 0.2)\n", ed, ed0, eg);
    EXPECT_LT(ed, 0.01);
    EXPECT_LT(eg, 0.01);
}

TEST(EditNdf, RotationTurnsTheAnisotropyAxis) {
    const NpfModel m = microfacet(0.15, 0.45, true);
    const NpfModel quarter = npf::edit::transform_ndf(m, npf::edit::rotation_matrix(90));
    const NpfModel thirty = npf::edit::transform_ndf(m, npf::edit::rotation_matrix(30));
    const double area = npf::edit::projected_area(m)[1];  // the analytic table's area on the grid
    const double e90 = d_error(quarter, 1, [&](double t, double p) { return ggx(t, p, 0.45, 0.15) / area; });
    const double g90 = g_error(quarter, 1, [](double t, double p) { return smith_g1(t, p, 0.45, 0.15); });
    const double a = 30.0 * kPi / 180.0;
    const double e30 = d_error(thirty, 1, [&](double t, double p) { return ggx(t, p - a, 0.15, 0.45); });
    const double g30 = g_error(thirty, 1, [&](double t, double p) { return smith_g1(t, p - a, 0.15, 0.45); });
    std::printf("[ measured ] rotations of GGX (0.15, 0.45): 90 deg D rel. RMS %.2g, G %.2g; 30 deg D %.4f, G %.4f\n", e90,
                g90, e30, g30);
    EXPECT_LT(e90, 1e-5);  // a whole number of cells: the table moves over exactly
    EXPECT_LT(g90, 1e-5);
    EXPECT_LT(e30, 0.02);
    EXPECT_LT(g30, 0.01);
}

TEST(EditNdf, RoughnessScaleSharpensAndBlurs) {
    const NpfModel m = microfacet(0.3, 0.3, false, false, 64);
    const NpfModel sharp = npf::edit::transform_ndf(m, npf::edit::roughness_matrix(0.5));
    const NpfModel blur = npf::edit::transform_ndf(m, npf::edit::roughness_matrix(2.0));
    EXPECT_EQ(sharp.d_phi, 1);  // an isotropic scale keeps an isotropic material isotropic
    EXPECT_EQ(blur.g_phi, 1);
    const double es = d_error(sharp, 0, [](double t, double p) { return ggx(t, p, 0.15, 0.15); });
    const double eb = d_error(blur, 0, [](double t, double p) { return ggx(t, p, 0.6, 0.6); });
    const double gs = g_error(sharp, 0, [](double t, double p) { return smith_g1(t, p, 0.15, 0.15); });
    const double gb = g_error(blur, 0, [](double t, double p) { return smith_g1(t, p, 0.6, 0.6); });
    std::printf("[ measured ] GGX 0.3 sharpened to 0.15: D %.4f, G %.4f; blurred to 0.6: D %.4f, G %.4f\n", es, gs, eb, gb);
    EXPECT_LT(es, 0.01);
    EXPECT_LT(eb, 0.01);
    EXPECT_LT(gs, 0.01);
    EXPECT_LT(gb, 0.01);
}

// Scaling anisotropy by s and then by 1 / s returns the original within the grid's
// interpolation error. That error is measured step by step: the first step against the analytic
// stretched GGX, the second as the same inverse stretch applied to a tabulation of that
// analytic stretched GGX, against the original GGX. The round trip may not exceed their sum.
TEST(EditNdf, StretchAndInverseStretchRoundTrip) {
    const double ax = 0.2, ay = 0.3;
    const NpfModel m = microfacet(ax, ay, true, true);
    // make_microfacet_factors: roughness 0.95 .. 1.05 times alpha across the channels.
    auto scale_of = [&](std::size_t c) { return 0.95 + 0.1 * double(c) / double(m.channel_count() - 1); };
    for (double s : {0.5, 2.0, 3.0}) {
        const NpfModel once = npf::edit::transform_ndf(m, npf::edit::stretch_matrix(s, 1.0));
        const NpfModel back = npf::edit::transform_ndf(once, npf::edit::stretch_matrix(1.0 / s, 1.0));
        const NpfModel exact_once = microfacet(s * ax, ay, true, true);
        const NpfModel second = npf::edit::transform_ndf(exact_once, npf::edit::stretch_matrix(1.0 / s, 1.0));
        double e1 = 0.0, e2 = 0.0, e_back = 0.0, e_g = 0.0;
        for (std::size_t c = 0; c < m.channel_count(); ++c) {
            const double k = scale_of(c);
            e1 = std::max(e1, d_error(once, c, [&](double t, double p) { return ggx(t, p, s * ax * k, ay * k); }));
            e2 = std::max(e2, d_error(second, c, [&](double t, double p) { return ggx(t, p, ax * k, ay * k); }));
            // The round trip against the original table itself (same grid, same cells).
            e_back = std::max(e_back, d_error(back, c, [&](double t, double p) {
                                  const int i = int(std::lround(std::sqrt(t / (0.5 * kPi)) * m.d_theta - 0.5));
                                  const int j = int(std::lround(p / (2.0 * kPi) * m.d_phi - 0.5));
                                  return std::max(0.0, m.D.at(c, std::size_t(i) * std::size_t(m.d_phi) + std::size_t(j)));
                              }));
            e_g = std::max(e_g, g_error(back, c, [&](double t, double p) {
                               const int i = int(std::lround(t / (0.5 * kPi) * m.g_theta - 0.5));
                               const int j = int(std::lround(p / (2.0 * kPi) * m.g_phi - 0.5));
                               return m.G.at(c, std::size_t(i) * std::size_t(m.g_phi) + std::size_t(j));
                           }));
        }
        std::printf("[ measured ] stretch %g then %g (D 32 x 64): steps' D rel. RMS %.4f + %.4f, round trip %.4f; "
                    "G round trip max abs %.4f (theta < 75 deg)\n",
                    s, 1.0 / s, e1, e2, e_back, e_g);
        EXPECT_LT(e_back, e1 + e2 + 1e-3);
        EXPECT_LT(e_back, 0.02);
        EXPECT_LT(e_g, 0.01);
        for (double a : npf::edit::projected_area(back)) EXPECT_NEAR(a, 1.0, 1e-3);
    }
}

TEST(EditNdf, SpectralModelIsRecompressedAtItsRank) {
    // A rank-2 spectral model: two roughnesses mixed in varying proportion across channels.
    MicrofacetSpec s;
    s.spectral = true;
    s.channels = 8;
    s.set_grid(24, 48, s.f_theta, 24, 48);
    s.alpha_x = 0.2;
    s.alpha_y = 0.4;
    npf::NpfFactors f = npf::testing::make_microfacet_factors(s);
    npf::CompressionOptions o;
    o.d_rank = 3;
    o.g_rank = 2;
    const NpfModel m = npf::compress_factors(f, o);
    npf::edit::EditRecord r;
    const NpfModel out = npf::edit::transform_ndf(m, npf::edit::stretch_matrix(1.5, 0.8), {}, &r);
    EXPECT_EQ(out.D.rank, 3);
    EXPECT_EQ(out.G.rank, 2);
    EXPECT_EQ(out.D.singular_values.size(), 8u);
    // The edited tables of a rank-3 model have rank 3: nothing beyond it.
    EXPECT_GT(out.D.kept_ratio, 1.0 - 1e-9);
    EXPECT_NO_THROW(out.validate("test"));
    npf::edit::NdfTransformOptions ratio;
    ratio.recompress = npf::edit::Recompress::KeptRatio;
    const NpfModel by_ratio = npf::edit::transform_ndf(m, npf::edit::stretch_matrix(1.5, 0.8), ratio);
    EXPECT_LE(by_ratio.D.rank, 3);
    std::printf("[ measured ] %s\n", r.summary.c_str());
}

TEST(EditNdf, PhiCellsOption) {
    const NpfModel m = microfacet(0.3, 0.3, false);
    npf::edit::NdfTransformOptions o;
    o.phi_cells = 40;
    const NpfModel out = npf::edit::transform_ndf(m, npf::edit::stretch_matrix(1.0, 2.0), o);
    EXPECT_EQ(out.d_phi, 40);
    EXPECT_EQ(out.g_phi, 40);
    EXPECT_FALSE(out.isotropic());
}

TEST(EditNdf, TiltingMatrixIsAppliedWithAWarning) {
    const NpfModel m = microfacet(0.3, 0.3, false);
    npf::edit::EditRecord r;
    const NpfModel out = npf::edit::transform_ndf(m, Mat3{{1, 0, 0.2, 0, 1, 0, 0, 0, 1}}, {}, &r);
    for (double a : npf::edit::projected_area(out)) EXPECT_NEAR(a, 1.0, 1e-3);
    ASSERT_FALSE(r.warnings.empty());
    EXPECT_NE(r.warnings[0].find("tilts"), std::string::npos);
}

TEST(EditNdf, BadMatricesAreErrors) {
    const NpfModel m = microfacet(0.3, 0.3, false);
    EXPECT_THROW(npf::edit::transform_ndf(m, Mat3{{1, 0, 0, 0, 1, 0, 0, 0, 0}}), npf::Error);
    EXPECT_THROW(npf::edit::transform_ndf(m, Mat3{{1, 2, 0, 2, 4, 0, 0, 0, 1}}), npf::Error);
    EXPECT_THROW(npf::edit::transform_ndf(m, Mat3{{NAN, 0, 0, 0, 1, 0, 0, 0, 1}}), npf::Error);
    EXPECT_THROW(npf::edit::stretch_matrix(0.0, 1.0), npf::Error);
    EXPECT_THROW(npf::edit::roughness_matrix(-1.0), npf::Error);
    try {
        npf::edit::transform_ndf(m, Mat3{{1, 2, 0, 2, 4, 0, 0, 0, 1}});
    } catch (const npf::Error& e) {
        EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
    }
}

}  // namespace
