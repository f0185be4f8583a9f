// Diffuse and specular colour edits (issue 7; docs/editing.md): a diffuse swap leaves D, F, G
// (and rho_s) untouched bit for bit, a specular swap leaves rho_d, D and G untouched and copies
// rho_s F, and colours cross between RGB and spectral materials as documented.
#include "npf_test_factors.h"

#include <npf/color/rgb_sigmoid.h>
#include <npf/color/spectrum.h>
#include <npf/fit/spectral_compression.h>
#include <npf/core/error.h>
#include <npf/edit/colour_edits.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace {

using npf::NpfModel;
constexpr double kPi = npf::kPiD;

NpfModel material(bool spectral, bool anisotropic, double rho_d, double alpha, int f_theta = 32, std::size_t channels = 12) {
    npf::testing::MicrofacetSpec s;
    s.spectral = spectral;
    s.channels = spectral ? channels : 3;
    s.rho_d = rho_d;
    s.rho_s = 0.2;
    s.alpha_x = alpha;
    s.alpha_y = anisotropic ? 2 * alpha : alpha;
    s.d_theta = 16;
    s.d_phi = anisotropic ? 32 : 1;
    s.g_theta = 16;
    s.g_phi = anisotropic ? 32 : 1;
    s.f_theta = f_theta;
    return npf::compress_factors(npf::testing::make_microfacet_factors(s), npf::CompressionOptions());
}

void expect_same_d_g(const NpfModel& a, const NpfModel& b) {
    EXPECT_EQ(a.D.basis, b.D.basis);
    EXPECT_EQ(a.D.weights, b.D.weights);
    EXPECT_EQ(a.D.singular_values, b.D.singular_values);
    EXPECT_EQ(a.G.basis, b.G.basis);
    EXPECT_EQ(a.G.weights, b.G.weights);
    EXPECT_EQ(a.d_phi, b.d_phi);
    EXPECT_EQ(a.g_phi, b.g_phi);
}

npf::color::Rgb colour_of(const NpfModel& m, const std::vector<float>& v) {
    const auto w = npf::color::linear_srgb_weights(m.channels.wavelengths());
    npf::color::Rgb rgb{0, 0, 0};
    for (std::size_t k = 0; k < 3; ++k) {
        for (std::size_t c = 0; c < v.size(); ++c) rgb[k] += w[k][c] * v[c];
    }
    return rgb;
}

TEST(EditColour, DiffuseSwapLeavesDFGUntouched) {
    for (bool spectral : {false, true}) {
        const NpfModel target = material(spectral, true, 0.05, 0.2);
        const NpfModel source = material(spectral, false, 0.15, 0.4);  // isotropic source, anisotropic target
        npf::edit::EditRecord r;
        const NpfModel out = npf::edit::replace_diffuse(target, source, 1.0, &r);
        expect_same_d_g(out, target);
        EXPECT_EQ(out.F, target.F);
        EXPECT_EQ(out.rho_s, target.rho_s);
        EXPECT_EQ(out.rho_d, source.rho_d);
        EXPECT_NE(r.summary.find("diffuse"), std::string::npos);
        EXPECT_TRUE(r.warnings.empty());
    }
}

TEST(EditColour, DiffuseAcrossChannelKinds) {
    const NpfModel rgb = material(false, false, 0.05, 0.2);
    const NpfModel spectral = material(true, false, 0.05, 0.2, 32, 31);  // 400..700 nm
    // Spectral into RGB: the colour of the source's albedo spectrum.
    npf::edit::EditRecord r1;
    const NpfModel to_rgb = npf::edit::replace_diffuse(rgb, spectral, 1.0, &r1);
    std::vector<float> albedo(spectral.rho_d.size());
    for (std::size_t c = 0; c < albedo.size(); ++c) albedo[c] = float(kPi * spectral.rho_d[c]);
    const npf::color::Rgb want = colour_of(spectral, albedo);
    for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(kPi * to_rgb.rho_d[k], want[k], 1e-5);
    expect_same_d_g(to_rgb, rgb);
    // RGB into spectral: the upsampled spectrum has the RGB colour back.
    const NpfModel to_spectral = npf::edit::replace_diffuse(spectral, to_rgb, 1.0);
    std::vector<float> back(to_spectral.rho_d.size());
    for (std::size_t c = 0; c < back.size(); ++c) back[c] = float(kPi * to_spectral.rho_d[c]);
    const npf::color::Rgb again = colour_of(to_spectral, back);
    for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(again[k], want[k], 5e-3);
    expect_same_d_g(to_spectral, spectral);
    EXPECT_EQ(to_spectral.F, spectral.F);
    // An sRGB colour into a spectral material: upsampled (sigmoid), colour kept. (Here rather than
    // below: the sigmoid's table is built once per process, in about half a second.)
    const NpfModel u = npf::edit::replace_diffuse_albedo(spectral, npf::color::Rgb{0.6, 0.3, 0.1});
    std::vector<float> a(u.rho_d.size());
    for (std::size_t c = 0; c < a.size(); ++c) a[c] = float(kPi * u.rho_d[c]);
    const npf::color::Rgb got = colour_of(u, a);
    EXPECT_NEAR(got[0], 0.6, 0.01);
    EXPECT_NEAR(got[1], 0.3, 0.01);
    EXPECT_NEAR(got[2], 0.1, 0.01);
}

TEST(EditColour, DiffuseFromColourAndSpectrum) {
    const NpfModel rgb = material(false, false, 0.05, 0.2);
    const NpfModel out = npf::edit::replace_diffuse_albedo(rgb, npf::color::Rgb{0.5, 0.25, 0.1});
    EXPECT_FLOAT_EQ(out.rho_d[0], float(0.5 / kPi));
    EXPECT_FLOAT_EQ(out.rho_d[2], float(0.1 / kPi));
    EXPECT_EQ(out.F, rgb.F);
    const NpfModel spectral = material(true, false, 0.05, 0.2, 32, 31);
    const npf::color::SampledSpectrum ramp({400.0, 700.0}, {0.2, 0.8});
    const NpfModel s = npf::edit::replace_diffuse_albedo(spectral, ramp);
    const auto& wl = spectral.channels.wavelengths();
    for (std::size_t c = 0; c < wl.size(); ++c) EXPECT_NEAR(kPi * s.rho_d[c], ramp(wl[c]), 1e-6);
    // The spectrum into an RGB material: its colour.
    const NpfModel r = npf::edit::replace_diffuse_albedo(rgb, ramp);
    const npf::color::Rgb want = npf::color::xyz_to_linear_srgb(npf::color::spectrum_to_xyz(ramp));
    for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(kPi * r.rho_d[k], want[k], 1e-6);
    EXPECT_THROW(npf::edit::replace_diffuse_albedo(rgb, npf::color::Rgb{-0.1, 0.2, 0.3}), npf::Error);
    EXPECT_THROW(npf::edit::replace_diffuse(rgb, rgb, -1.0), npf::Error);
}

TEST(EditColour, SpecularSwapKeepsTheHighlightShape) {
    const NpfModel target = material(true, true, 0.05, 0.15);
    npf::testing::MicrofacetSpec s;
    s.spectral = true;
    s.channels = 12;
    s.rho_s = 0.3;
    s.f_theta = 32;
    npf::NpfFactors f = npf::testing::make_microfacet_factors(s);
    for (std::size_t c = 0; c < 12; ++c) {  // a coloured specular: F falls off differently per channel
        for (int k = 0; k < 32; ++k) f.F[c * 32 + std::size_t(k)] *= float(1.0 + 0.02 * double(c) * k / 31.0);
        f.rho_s[c] = float(0.1 + 0.02 * double(c));
    }
    const NpfModel source = npf::compress_factors(f, npf::CompressionOptions());
    npf::edit::EditRecord r;
    const NpfModel out = npf::edit::replace_specular(target, source, {1.0, false}, &r);
    expect_same_d_g(out, target);
    EXPECT_EQ(out.rho_d, target.rho_d);
    EXPECT_EQ(out.rho_s, source.rho_s);
    EXPECT_EQ(out.F, source.F);
    EXPECT_NE(r.summary.find("D and G unchanged"), std::string::npos);
    // The highlight's shape: f_r - rho_d changes by the ratio of rho_s F only.
    const npf::Vec3 wi = npf::spherical_direction(0.4f, 0.3f), wo = npf::spherical_direction(0.5f, 3.3f);
    for (std::size_t c = 0; c < 12; ++c) {
        const double before = target.eval(c, wi, wo) - target.rho_d[c], after = out.eval(c, wi, wo) - out.rho_d[c];
        EXPECT_GT(before, 0.0);
        EXPECT_NEAR(after / before, double(source.rho_s[c]) / target.rho_s[c] * (source.F[c * 32 + 9] / target.F[c * 32 + 9]), 0.05);
    }
}

TEST(EditColour, SpecularFromAnotherGridAndChannelKind) {
    const NpfModel target = material(true, false, 0.05, 0.15, 24);
    const NpfModel source = material(false, false, 0.05, 0.3, 40);
    npf::edit::EditRecord r;
    const NpfModel out = npf::edit::replace_specular(target, source, {2.0, false}, &r);
    expect_same_d_g(out, target);
    ASSERT_EQ(out.F.size(), target.F.size());
    for (std::size_t c = 0; c < out.channel_count(); ++c) {
        EXPECT_FLOAT_EQ(out.F[c * 24], 1.f);  // the gauge
        // Grey source (rho_s 0.2, same Schlick in all channels): the upsampled colour is flat.
        EXPECT_NEAR(out.rho_s[c], 2.0 * 0.2 * source.F[0], 2e-3);
    }
    // F follows the source's Schlick curve resampled on 24 cells: compare at the last cell.
    const double theta = 0.5 * kPi * 23.5 / 24, m = 1.0 - std::cos(theta);
    EXPECT_NEAR(out.F[23] * out.rho_s[0] / 2.0, 0.2 * (0.5 + 0.5 * std::pow(m, 5)) / 0.5, 0.01);
    // keep_brightness: the luminance of rho_s F(0) stays the target's; the colour is the source's.
    const NpfModel kept = npf::edit::replace_specular(target, source, {1.0, true});
    const auto y = npf::color::luminance_weights(target.channels.wavelengths());
    double y_before = 0.0, y_after = 0.0;
    for (std::size_t c = 0; c < y.size(); ++c) {
        y_before += y[c] * target.rho_s[c] * target.F[c * 24];
        y_after += y[c] * kept.rho_s[c] * kept.F[c * 24];
    }
    EXPECT_NEAR(y_after, y_before, 1e-6 * y_before);
}

}  // namespace
