// The directional-albedo check that follows every edit (docs/editing.md): the diffuse term gives
// pi rho_d exactly, the specular integral over the half vector agrees with a brute-force
// integral over the outgoing direction, a white microfacet material stays below 1, and edits that
// push the albedo above 1 are reported.
#include "npf_test_factors.h"

#include <npf/fit/spectral_compression.h>
#include <npf/shading/npf_albedo.h>
#include <npf/edit/recipe.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using npf::NpfModel;
using npf::Vec3;
constexpr double kPi = npf::kPiD;

NpfModel material(double alpha_x, double alpha_y, double rho_d, double rho_s, bool anisotropic = false) {
    npf::testing::MicrofacetSpec s;
    s.alpha_x = alpha_x;
    s.alpha_y = alpha_y;
    s.rho_d = rho_d;
    s.rho_s = rho_s;
    s.d_theta = 48;
    s.d_phi = anisotropic ? 96 : 1;
    s.g_theta = 48;
    s.g_phi = anisotropic ? 96 : 1;
    s.f_theta = 48;
    return npf::compress_factors(npf::testing::make_microfacet_factors(s), npf::CompressionOptions());
}

// Midpoint rule over (cos theta_o, phi_o): a fine, direct integral of f_r cos over the hemisphere.
std::vector<double> brute_force_albedo(const NpfModel& m, const Vec3& wi, int n) {
    std::vector<double> a(m.channel_count(), 0.0);
    std::vector<double> f(m.channel_count());
    for (int i = 0; i < n; ++i) {
        const double ct = (i + 0.5) / n, st = std::sqrt(1.0 - ct * ct);
        for (int j = 0; j < 2 * n; ++j) {
            const double p = kPi * (j + 0.5) / n;
            const Vec3 wo{float(st * std::cos(p)), float(st * std::sin(p)), float(ct)};
            m.eval_all(wi, wo, f.data());
            for (std::size_t c = 0; c < a.size(); ++c) a[c] += f[c] * ct * (1.0 / n) * (kPi / n);
        }
    }
    return a;
}

TEST(EditAlbedo, DiffuseTermIsPiRhoD) {
    const NpfModel m = material(0.3, 0.3, 0.2, 0.0);
    for (double t : {0.0, 45.0, 80.0}) {
        const std::vector<double> a = npf::npf_directional_albedo(m, npf::spherical_direction(float(t * kPi / 180), 0.f));
        for (std::size_t c = 0; c < a.size(); ++c) EXPECT_NEAR(a[c], kPi * m.rho_d[c], 1e-6);
    }
}

TEST(EditAlbedo, HalfVectorIntegralMatchesBruteForce) {
    // make_microfacet_factors: F is Schlick with F0 = 0.5 divided by 0.5 (the gauge), so
    // rho_s = F0 / 4 = 0.125 is the microfacet material D F G / (4 cos cos).
    for (bool aniso : {false, true}) {
        const NpfModel m = material(0.25, aniso ? 0.5 : 0.25, 0.05, 0.125, aniso);
        for (double t : {0.0, 40.0, 70.0}) {
            const Vec3 wi = npf::spherical_direction(float(t * kPi / 180), 0.7f);
            const std::vector<double> a = npf::npf_directional_albedo(m, wi);
            const std::vector<double> b = brute_force_albedo(m, wi, 400);
            std::printf("[ measured ] %s, theta_i %g: albedo %.5f (half-vector grid), %.5f (brute force)\n",
                        aniso ? "anisotropic" : "isotropic", t, a[0], b[0]);
            for (std::size_t c = 0; c < a.size(); ++c) EXPECT_NEAR(a[c], b[c], 2e-3 * b[c]);
        }
    }
}

TEST(EditAlbedo, WhiteMicrofacetMaterialStaysBelowOne) {
    // F0 = 1 would be rho_s = 0.25 with F = 1; Schlick with F0 = 0.5 rises to 2 at grazing in
    // the gauge, so rho_s = 0.25 is a material brighter than any real one near grazing and a
    // real white one near normal incidence.
    const NpfModel sharp = material(0.05, 0.05, 0.0, 0.125);
    const npf::AlbedoPeak r = npf::npf_largest_albedo(sharp);
    std::printf("[ measured ] GGX 0.05, Schlick F0 0.5: largest albedo %.4f at theta_i %g\n", r.max, r.theta_deg);
    EXPECT_LE(r.max, 1.0);
    EXPECT_GT(r.max, 0.4);
}

TEST(EditAlbedo, EditsThatBreakEnergyConservationAreReported) {
    const NpfModel m = material(0.3, 0.3, 0.05, 0.125);
    npf::edit::EditOptions o;
    // A white diffuse albedo on top of a specular lobe: more than 1 in total.
    const auto step = npf::edit::EditStep::diffuse_albedo(npf::color::Rgb{1.0, 1.0, 1.0}, "white");
    const npf::edit::EditResult r = npf::edit::apply_edits(m, {step}, o);
    ASSERT_EQ(r.records.size(), 1u);
    ASSERT_FALSE(r.records[0].warnings.empty());
    EXPECT_NE(r.records[0].warnings.back().find("reflects more light than it receives"), std::string::npos);
    EXPECT_GT(r.output_albedo.max, 1.0);
    EXPECT_LT(r.input_albedo.max, 1.0);
    // The warning is in the history too.
    const auto history = npf::edit::edit_history(r.model);
    ASSERT_EQ(history.size(), 1u);
    EXPECT_NE(history[0].second.find("WARNING"), std::string::npos) << history[0].second;
    // A modest colour does not warn.
    const auto mild = npf::edit::EditStep::diffuse_albedo(npf::color::Rgb{0.5, 0.2, 0.1}, "mild");
    const npf::edit::EditResult ok = npf::edit::apply_edits(m, {mild}, o);
    EXPECT_TRUE(ok.records[0].warnings.empty());
}

}  // namespace
