// Thin-film Fresnel edits (issue 7; docs/editing.md): a zero-thickness film returns the base
// Fresnel (ratio mode: the material's own F, bit for bit; replace mode: the given base's Fresnel
// curve), the film follows the Airy reflectance, the fitted base recovers known indices, and RGB
// materials get the film's colour.
#include "npf_test_factors.h"

#include <npf/materials/analytic/fresnel.h>
#include <npf/fit/spectral_compression.h>
#include <npf/materials/material_recipe.h>
#include <npf/core/error.h>
#include <npf/edit/recipe.h>
#include <npf/edit/thin_film.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using npf::NpfModel, npf::color::SampledSpectrum, npf::edit::FilmMode, npf::edit::ThinFilm;
constexpr double kPi = npf::kPiD;

// A microfacet material whose F is `fresnel` (in the gauge: divided by its first cell) and whose
// rho_s is F0 / 4 (the microfacet relation).
NpfModel with_fresnel(const npf::Fresnel& fresnel, bool spectral, std::size_t channels = 16, int f_theta = 45) {
    npf::testing::MicrofacetSpec s;
    s.spectral = spectral;
    s.channels = spectral ? channels : 3;
    s.d_theta = 16;
    s.g_theta = 16;
    s.f_theta = f_theta;
    npf::NpfFactors f = npf::testing::make_microfacet_factors(s);
    const double rgb_wl[3] = {611, 549, 464};
    for (std::size_t c = 0; c < f.channel_count(); ++c) {
        const double l = spectral ? double(f.channels.wavelengths()[c]) : rgb_wl[c];
        const double f0 = fresnel.eval(std::cos(0.5 * kPi * 0.5 / f_theta), l);
        for (int k = 0; k < f_theta; ++k) {
            f.F[c * std::size_t(f_theta) + std::size_t(k)] = float(fresnel.eval(std::cos(0.5 * kPi * (k + 0.5) / f_theta), l) / f0);
        }
        f.rho_s[c] = float(f0 / 4.0);
    }
    return npf::compress_factors(f, npf::CompressionOptions());
}

ThinFilm film(double thickness, double eta, FilmMode mode = FilmMode::Ratio) {
    ThinFilm t;
    t.thickness_nm = thickness;
    t.film_eta = SampledSpectrum::constant(eta);
    t.mode = mode;
    return t;
}

TEST(EditThinFilm, ZeroThicknessInRatioModeChangesNothing) {
    const npf::Fresnel gold = npf::conductor_fresnel("Au", "test");
    for (bool spectral : {false, true}) {
        const NpfModel m = with_fresnel(gold, spectral);
        for (bool fitted : {true, false}) {
            ThinFilm t = film(0.0, 1.4);
            if (!fitted) t.base = npf::edit::parse_film_base("1.6", "test");
            const NpfModel out = npf::edit::apply_thin_film(m, t);
            EXPECT_EQ(out.F, m.F);
            EXPECT_EQ(out.rho_s, m.rho_s);
            EXPECT_EQ(out.rho_d, m.rho_d);
            EXPECT_EQ(out.D.basis, m.D.basis);
            EXPECT_EQ(out.G.weights, m.G.weights);
        }
    }
}

TEST(EditThinFilm, ZeroThicknessInReplaceModeGivesTheBaseFresnel) {
    const NpfModel m = with_fresnel(npf::Fresnel::dielectric(SampledSpectrum::constant(1.5)), true);
    ThinFilm t = film(0.0, 1.33, FilmMode::Replace);
    t.base = npf::edit::parse_film_base("Au", "test");
    const NpfModel out = npf::edit::apply_thin_film(m, t);
    const npf::Fresnel gold = npf::conductor_fresnel("Au", "test");
    double worst = 0.0;
    const int n = m.f_theta;
    for (std::size_t c = 0; c < m.channel_count(); ++c) {
        const double l = m.channels.wavelengths()[c];
        const double r0 = gold.eval(std::cos(0.5 * kPi * 0.5 / n), l);
        for (int k = 0; k < n; ++k) {
            const double want = gold.eval(std::cos(0.5 * kPi * (k + 0.5) / n), l) / r0;
            worst = std::max(worst, std::fabs(out.F[c * std::size_t(n) + std::size_t(k)] - want));
        }
        // rho_s F(0) keeps its value: the film of thickness 0 changes nothing at normal incidence.
        EXPECT_FLOAT_EQ(out.rho_s[c], m.rho_s[c] * m.F[c * std::size_t(n)]);
    }
    std::printf("[ measured ] zero-thickness film, replace mode, gold base: F off gold's Fresnel by %.2g at most\n", worst);
    EXPECT_LT(worst, 1e-6);
}

TEST(EditThinFilm, FilmFollowsTheAiryReflectance) {
    const SampledSpectrum base_eta = SampledSpectrum::constant(1.5);
    const NpfModel m = with_fresnel(npf::Fresnel::dielectric(base_eta), true, 31);
    ThinFilm t = film(615.0, 1.3, FilmMode::Replace);
    t.base = npf::edit::parse_film_base("1.5", "test");
    npf::edit::EditRecord r;
    const NpfModel out = npf::edit::apply_thin_film(m, t, &r);
    const npf::Fresnel airy = npf::Fresnel::thin_film(615.0, SampledSpectrum::constant(1.3), base_eta, SampledSpectrum::constant(0));
    const npf::Fresnel bare = npf::Fresnel::dielectric(base_eta);
    const int n = m.f_theta;
    double worst = 0.0;
    for (std::size_t c = 0; c < m.channel_count(); ++c) {
        const double l = m.channels.wavelengths()[c];
        const double k0 = double(m.rho_s[c]) * m.F[c * std::size_t(n)];
        const double rb0 = bare.eval(std::cos(0.5 * kPi * 0.5 / n), l);
        for (int k = 0; k < n; ++k) {
            const double want = k0 * airy.eval(std::cos(0.5 * kPi * (k + 0.5) / n), l) / rb0;
            const double got = double(out.rho_s[c]) * out.F[c * std::size_t(n) + std::size_t(k)];
            worst = std::max(worst, std::fabs(got - want) / want);
        }
    }
    std::printf("[ measured ] 615 nm film of index 1.3 on glass: rho_s F off K(0) R_film / R_bare(0) by %.2g (relative)\n", worst);
    EXPECT_LT(worst, 1e-5);
    // The ratio mode on a material whose F is exactly the base's Fresnel gives the same.
    ThinFilm tr = t;
    tr.mode = FilmMode::Ratio;
    const NpfModel ratio = npf::edit::apply_thin_film(m, tr);
    for (std::size_t i = 0; i < ratio.F.size(); ++i) {
        const std::size_t c = i / std::size_t(n);
        EXPECT_NEAR(ratio.rho_s[c] * ratio.F[i], out.rho_s[c] * out.F[i], 1e-5 * out.rho_s[c] * out.F[i]);
    }
}

TEST(EditThinFilm, QuarterWaveFilmCancelsTheReflection) {
    const NpfModel m = with_fresnel(npf::Fresnel::dielectric(SampledSpectrum::constant(1.5)), true, 31);
    const double eta2 = std::sqrt(1.5), d = 550.0 / (4.0 * eta2);
    ThinFilm t = film(d, eta2);
    t.base = npf::edit::parse_film_base("1.5", "test");
    const NpfModel out = npf::edit::apply_thin_film(m, t);
    const auto& wl = m.channels.wavelengths();
    for (std::size_t c = 0; c < wl.size(); ++c) {
        if (std::fabs(wl[c] - 550.f) < 1.f) {
            EXPECT_LT(out.rho_s[c], 1e-3 * m.rho_s[c]);
            EXPECT_NO_THROW(out.validate("test"));
        }
    }
}

TEST(EditThinFilm, FittedBaseRecoversKnownIndices) {
    const NpfModel glass = with_fresnel(npf::Fresnel::dielectric(SampledSpectrum::constant(1.5)), true);
    const npf::edit::FittedBase g = npf::edit::fit_base_ior(glass);
    for (std::size_t c = 0; c < g.eta.size(); ++c) {
        EXPECT_NEAR(g.eta[c], 1.5, 2e-3);
        EXPECT_NEAR(g.k[c], 0.0, 0.02);
        EXPECT_LT(g.rms[c], 1e-3);
    }
    const npf::Fresnel gold = npf::conductor_fresnel("Au", "test");
    const NpfModel metal = with_fresnel(gold, true);
    const npf::edit::FittedBase a = npf::edit::fit_base_ior(metal);
    const npf::edit::FilmBase tables = npf::edit::parse_film_base("Au", "test");
    double worst_rms = 0.0;
    for (std::size_t c = 0; c < a.eta.size(); ++c) {
        const double l = a.wavelengths_nm[c];
        EXPECT_NEAR(a.f0[c], gold.eval(std::cos(0.5 * kPi * 0.5 / metal.f_theta), l), 1e-6);
        worst_rms = std::max(worst_rms, a.rms[c]);
    }
    std::printf("[ measured ] fitted base: glass eta %.4f k %.4f; gold at %g nm eta %.3f k %.3f (tables), fitted %.3f %.3f, "
                "curve RMS up to %.2g\n",
                g.eta[0], g.k[0], a.wavelengths_nm[8], tables.eta(a.wavelengths_nm[8]), tables.k(a.wavelengths_nm[8]), a.eta[8],
                a.k[8], worst_rms);
    EXPECT_LT(worst_rms, 2e-3);
    EXPECT_EQ(a.clamped_f0, 0u);
}

TEST(EditThinFilm, RgbMaterialGetsTheFilmsColour) {
    const NpfModel m = with_fresnel(npf::conductor_fresnel("Al", "test"), false);
    npf::edit::EditRecord r;
    const NpfModel out = npf::edit::apply_thin_film(m, film(450.0, 1.33), &r);
    EXPECT_NE(out.rho_s, m.rho_s);
    EXPECT_EQ(out.D.basis, m.D.basis);
    for (std::size_t c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(out.F[c * std::size_t(out.f_theta)], 1.f);
    std::printf("[ measured ] 450 nm film of index 1.33 on fitted aluminium (RGB): rho_s (%.4f, %.4f, %.4f) -> (%.4f, %.4f, %.4f)\n",
                m.rho_s[0], m.rho_s[1], m.rho_s[2], out.rho_s[0], out.rho_s[1], out.rho_s[2]);
    // A thick film on a coarse spectral grid aliases: warned.
    const NpfModel coarse = with_fresnel(npf::conductor_fresnel("Al", "test"), true, 7);
    npf::edit::EditRecord w;
    npf::edit::apply_thin_film(coarse, film(2000.0, 1.5), &w);
    ASSERT_FALSE(w.warnings.empty());
    EXPECT_NE(w.warnings.back().find("fringes"), std::string::npos);
}

TEST(EditThinFilm, BadParametersAreErrors) {
    const NpfModel m = with_fresnel(npf::Fresnel::dielectric(SampledSpectrum::constant(1.5)), false);
    EXPECT_THROW(npf::edit::apply_thin_film(m, film(-1.0, 1.3)), npf::Error);
    EXPECT_THROW(npf::edit::apply_thin_film(m, film(100.0, 0.0)), npf::Error);
    EXPECT_THROW(npf::edit::parse_film_base("Unobtainium", "base"), npf::Error);
    EXPECT_THROW(npf::edit::parse_film_base("-1.5", "base"), npf::Error);
    ThinFilm air = film(100.0, 1.3);
    air.base = npf::edit::parse_film_base("1", "test");
    EXPECT_THROW(npf::edit::apply_thin_film(m, air), npf::Error);
}

}  // namespace
