// The NPF fitter (AWLS): where the model holds exactly (one microfacet lobe plus a diffuse
// term) the fit recovers the material and its factors; at the extremes (mirror-sharp, purely
// diffuse, one wavelength, zeros, tiny, huge and invalid values) it stays finite and sensible.
#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/converter/convert_settings_table.h>
#include <npf/fit/awls.h>
#include <npf/fit/fit_error.h>
#include <npf/materials/open_material.h>
#include <npf/core/error.h>
#include <npf/core/simd_isa.h>

#include "synthetic_rgl.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace {

using npf::AnalyticBrdf;
using npf::Vec3d;

npf::AnalyticMaterial plastic(float ax, float ay) {
    npf::AnalyticMaterial m;
    m.name = "fit test";
    npf::SpecularLobe lobe;
    lobe.ndf.alpha_x = ax;
    lobe.ndf.alpha_y = ay;
    lobe.fresnel = npf::Fresnel::schlick(npf::color::SampledSpectrum({400.0, 700.0}, {0.9, 0.6}));
    m.specular.push_back(lobe);
    m.diffuse = npf::color::SampledSpectrum({400.0, 700.0}, {0.1, 0.3});
    m.wavelengths = {450.f, 550.f, 650.f};
    return m;
}

npf::BrdfSpaceError error_of(const npf::Brdf& source, const npf::NpfFactors& f, int pairs = 20000) {
    return npf::brdf_space_error(source, f.channels, [&](const npf::Vec3& wi, const npf::Vec3& wo, double* out) {
        for (std::size_t c = 0; c < f.channel_count(); ++c) out[c] = f.eval(c, Vec3d{wi.x, wi.y, wi.z}, Vec3d{wo.x, wo.y, wo.z});
    }, pairs);
}

bool all_finite(const npf::NpfFactors& f) {
    for (const auto* v : {&f.rho_d, &f.rho_s, &f.D, &f.F, &f.G}) {
        for (float x : *v) {
            if (!std::isfinite(x) || x < 0.f) return false;
        }
    }
    return true;
}

npf::AwlsOptions isotropic_options(int n, const npf::Channels& channels) {
    npf::AwlsOptions o;
    o.grid = {n, 1, n, 2 * n};
    o.g_theta = n;
    o.g_phi = 1;
    o.channels = channels;
    return o;
}

TEST(Awls, RecoversAnIsotropicMicrofacetMaterial) {
    const AnalyticBrdf source(plastic(0.2f, 0.2f));
    npf::AwlsOptions o = isotropic_options(90, npf::Channels::spectral({450.f, 550.f, 650.f}));
    npf::AwlsReport report;
    const npf::NpfFactors f = npf::fit_npf(source, o, &report);
    const npf::BrdfSpaceError e = error_of(source, f);
    for (std::size_t c = 0; c < 3; ++c) {
        std::printf("[ awls     ] channel %zu: %d sweeps, weighted error %.2e, BRDF-space relative RMS %.3f %%, rho_d %.4f\n", c,
                    report.iterations[c], report.relative_error[c], 100.0 * e.relative_rms[c], f.rho_d[c]);
        EXPECT_LT(e.relative_rms[c], 0.01) << "channel " << c;
        EXPECT_NEAR(f.rho_d[c] * npf::kPiD, 0.1 + 0.2 * (450.0 + 100.0 * c - 400.0) / 300.0, 0.015) << "diffuse albedo";
    }
    EXPECT_TRUE(all_finite(f));
}

// The factors themselves, in the gauge of npf_factors.h, against the material's own D, F and G:
// D (already of projected area 1), F / F(0) and Smith's G1 / G1(0), where the data constrain
// them (D where the peak is, theta below 75 degrees).
TEST(Awls, FittedFactorsMatchTheTrueOnes) {
    npf::AnalyticMaterial m = plastic(0.2f, 0.2f);
    const AnalyticBrdf source(m);
    npf::AwlsOptions o = isotropic_options(90, npf::Channels::spectral({550.f}));
    o.bound_g = true;  // `--g-prior smith`, for microfacet materials
    const npf::NpfFactors f = npf::fit_npf(source, o);
    const npf::SpecularLobe& lobe = m.specular[0];
    double d_num = 0.0, d_den = 0.0;
    for (int i = 0; i < o.grid.theta_h; ++i) {
        const double th = o.grid.theta_h_at(i);
        if (th > 60.0 * npf::kPiD / 180.0) break;
        const double truth = lobe.ndf.eval(npf::Vec3(float(std::sin(th)), 0.f, float(std::cos(th))));
        d_num += (f.D[std::size_t(i)] - truth) * (f.D[std::size_t(i)] - truth) * std::sin(th);
        d_den += truth * truth * std::sin(th);
    }
    double f_max = 0.0, g_max = 0.0;
    const double f0 = lobe.fresnel.eval(1.0, 550.0);
    for (int k = 0; k < o.grid.theta_d; ++k) {
        const double td = o.grid.theta_d_at(k);
        if (td > 75.0 * npf::kPiD / 180.0) break;
        f_max = std::max(f_max, std::abs(f.F[std::size_t(k)] - lobe.fresnel.eval(std::cos(td), 550.0) / f0));
    }
    const npf::Vec3 up(0.f, 0.f, 1.f);
    const double g0 = lobe.ndf.smith_g1(npf::Vec3(float(std::sin(0.25 * npf::kPiD / 90)), 0.f, float(std::cos(0.25 * npf::kPiD / 90))), up);
    for (int k = 0; k < o.g_theta; ++k) {
        const double t = (k + 0.5) * 0.5 * npf::kPiD / o.g_theta;
        if (t > 75.0 * npf::kPiD / 180.0) break;
        const npf::Vec3 w(float(std::sin(t)), 0.f, float(std::cos(t)));
        g_max = std::max(g_max, std::abs(f.G[std::size_t(k)] - lobe.ndf.smith_g1(w, up) / g0));
    }
    const double d_rel = std::sqrt(d_num / d_den);
    // rho_s = weight F(0) in this gauge; the NPF model's 1/4 goes into D F G G: rho_s D ... / 4.
    std::printf("[ awls     ] factor errors: D relative RMS %.3f %%, F max abs %.4f, G max abs %.4f, rho_s %.4f (F0/4 = %.4f)\n",
                100.0 * d_rel, f_max, g_max, f.rho_s[0], f0 / 4.0);
    // The bounds are what the fit achieves (docs/fitting.md): the data constrain the split
    // between F and G at large angles only weakly.
    EXPECT_LT(d_rel, 0.03);
    EXPECT_LT(f_max, 0.2);
    EXPECT_LT(g_max, 0.1);
    EXPECT_NEAR(f.rho_s[0], f0 / 4.0, 0.03 * f0 / 4.0);
}

// The acceleration (Anderson mixing of the last sweeps) against plain alternation: lower error
// after the same sweeps, and after 150 sweeps lower than plain alternation reaches in 300 (this
// material's valley is long: plain alternation still gains after 1000 sweeps).
TEST(Awls, ConvergesFasterWithExtrapolation) {
    const AnalyticBrdf source(plastic(0.3f, 0.3f));
    npf::AwlsOptions o = isotropic_options(32, npf::Channels::spectral({550.f}));
    o.tolerance = 0.0;
    o.max_iterations = 150;
    o.g_pin = 0.0;  // the pin's optimum is another than the unpinned crawl's: compare without it
    npf::AwlsReport fast, plain, plain_long;
    npf::fit_npf(source, o, &fast);
    o.acceleration = npf::AwlsOptions::Acceleration::None;
    npf::fit_npf(source, o, &plain);
    o.max_iterations = 300;
    npf::fit_npf(source, o, &plain_long);
    std::printf("[ awls     ] weighted error after 150 sweeps: %.4e accelerated, %.4e plain (%.4e after 300)\n", fast.relative_error[0],
                plain.relative_error[0], plain_long.relative_error[0]);
    EXPECT_LT(fast.relative_error[0], plain.relative_error[0]);
    EXPECT_LT(fast.relative_error[0], plain_long.relative_error[0]);
}

// Issue 16: with the compressive weight, every block of brushed copper crawled into the sweep
// cap (F rising and G falling together towards grazing angles, ~3e-5 of the error per sweep,
// while the error's float rounding, ~1e-5, made the line search accept and reject at random).
// A small spectral copy of the recipe (16 wavelengths, one block, the production tolerance and
// cap) must stop by its tolerance, and at an error no higher than the capped fit's.
// A small copy of the brushed copper recipe: `count` of its wavelengths spread over its range, on
// a 24 x 32 x 24 x 32 grid, the production tolerance and cap.
struct SmallCopper {
    std::unique_ptr<npf::Brdf> source;
    std::vector<float> wl;
    npf::AwlsOptions o;
};
SmallCopper small_copper(std::size_t count, int phi_d_samples) {
    SmallCopper c;
    c.source = npf::open_material(std::string(NPF_SOURCE_DIR) + "/configs/materials/brushed_copper.yaml");
    const std::vector<float>& all = c.source->info().channels.wavelengths();
    for (std::size_t k = 0; k < count; ++k) c.wl.push_back(all[k * (all.size() - 1) / (count - 1)]);
    c.o.grid = {24, 32, 24, 32};
    c.o.g_theta = 24;
    c.o.g_phi = 32;
    c.o.phi_d_samples = phi_d_samples;
    c.o.channels = npf::Channels::spectral(c.wl);
    c.o.max_iterations = 200;
    c.o.tolerance = 1e-5;
    return c;
}

TEST(Awls, SpectralCopperStopsByItsTolerance) {
    SmallCopper copper = small_copper(16, 8);
    const npf::Brdf* source = copper.source.get();
    const std::vector<float>& wl = copper.wl;
    npf::AwlsOptions& o = copper.o;
    npf::AwlsReport r, capped;
    npf::fit_npf(*source, o, &r);
    o.tolerance = 0.0;
    npf::fit_npf(*source, o, &capped);
    double worst = 0.0;
    for (std::size_t c = 0; c < wl.size(); ++c) worst = std::max(worst, r.relative_error[c] / capped.relative_error[c] - 1.0);
    std::printf("[ awls     ] copper, 16 wavelengths: %d sweeps (cap %d); weighted error at most %.2e above 200 sweeps' (relative)\n",
                r.iterations[0], o.max_iterations, worst);
    EXPECT_LT(r.iterations[0], o.max_iterations);
    EXPECT_LT(worst, 1e-3);
}

// Issue 19: the later blocks of a spectral fit are pinned to the G the cold block converged to,
// not each to its predecessor's. Pinned along a chain, G drifted block after block (brushed
// copper's G is the same at every wavelength, yet the fitted one was not: the SVD compression then
// cut what the fit had gained) and every warm block crawled along with it. A small copy of the
// recipe, 64 wavelengths in four blocks: G of every channel within a few per cent of the anchor's,
// and the blocks after the first warm one done in a few sweeps.
TEST(Awls, LaterBlocksArePinnedToTheColdBlocksG) {
    const SmallCopper copper = small_copper(64, 4);
    const npf::Brdf* source = copper.source.get();
    const std::vector<float>& wl = copper.wl;
    const npf::AwlsOptions& o = copper.o;
    npf::AwlsReport r;
    const npf::NpfFactors f = npf::fit_npf(*source, o, &r);
    ASSERT_TRUE(all_finite(f));
    // G of each channel against the anchor's (channel 15, the cold block's last), where G matters.
    const std::size_t cells = f.g_size();
    const float* anchor = &f.G[15 * cells];
    double worst = 0.0;
    for (std::size_t c = 0; c < f.channel_count(); ++c) {
        for (std::size_t k = 0; k < cells; ++k) {
            if (anchor[k] > 0.2f) worst = std::max(worst, std::abs(double(f.G[c * cells + k]) / anchor[k] - 1.0));
        }
    }
    // The first warm block still moves from the cold block's G (its pin is that G, as before);
    // the blocks after it start where their pin holds them (with the chain: 19 and 18 sweeps, G
    // 5.7 % from the anchor's; pinned to it: 4 and 4, 3.1 %).
    int later = 0;
    for (std::size_t c = 32; c < wl.size(); ++c) later = std::max(later, r.iterations[c]);
    std::printf("[ awls     ] copper, 64 wavelengths: sweeps per block %d, %d, %d, %d; G at most %.2f %% from the anchor's\n",
                r.iterations[0], r.iterations[16], r.iterations[32], r.iterations[48], 100.0 * worst);
    EXPECT_LT(worst, 0.045);
    EXPECT_LE(later, 8);
}

// Issue 19: a material the model represents almost exactly (red_plastic.yaml's isotropic GGX
// lobe, fitted to a few millionths of its weighted energy) drifted by gains far below anything a
// render shows and ran into the cap; below 1e-4 of the energy the stopping test now judges the
// gains against that floor. The first block of its production conversion (16 of its 41
// wavelengths, the paper's grid); with the floor at 1e-5 it ran to the cap. Slow (about 15 s).
TEST(SlowAwls, NearlyExactFitStopsByItsTolerance) {
    const std::unique_ptr<npf::Brdf> source = npf::open_material(std::string(NPF_SOURCE_DIR) + "/configs/materials/red_plastic.yaml");
    const std::vector<float>& all = source->info().channels.wavelengths();
    npf::AwlsOptions o;
    o.grid = {90, 1, 90, 180};  // the production preset's
    o.g_theta = 90;
    o.g_phi = 1;
    o.channels = npf::Channels::spectral(std::vector<float>(all.begin(), all.begin() + 16));
    o.max_iterations = 200;
    o.tolerance = 1e-5;
    npf::AwlsReport r;
    npf::fit_npf(*source, o, &r);
    double worst = 0.0;
    for (double e : r.relative_error) worst = std::max(worst, e);
    std::printf("[ awls     ] red plastic, first 16 wavelengths: %d sweeps (cap %d), relative error at most %.2e\n",
                r.iterations[0], o.max_iterations, worst);
    EXPECT_LT(worst, 3e-3);  // the model holds: RMS below 0.3 %
    EXPECT_LT(r.iterations[0], o.max_iterations);
}

// Issue 16: on measured files the alternation drifts along the near-symmetry G -> G s,
// F -> F / s^2 at a constant small gain per sweep (ilm: 1.1e-4 of the error per sweep, ten times
// the tolerance, for all 200 sweeps) and so always stopped at its cap. The pin holds G near its
// first sweep's: the same fit then stops by its tolerance, at a weighted error within a few per
// cent of the capped drift's.
TEST(Awls, MeasuredMaterialStopsByItsToleranceWithTheGPin) {
    const std::string path = npf::testing::shared_data_file("rgl/ilm_l3_37_metallic_rgb.bsdf");
    if (path.empty()) GTEST_SKIP() << "rgl/ilm_l3_37_metallic_rgb.bsdf not found in the shared data folder";
    const std::unique_ptr<npf::Brdf> source = npf::open_material(path);
    npf::AwlsOptions o = isotropic_options(32, npf::Channels::rgb());
    o.max_iterations = 200;
    o.tolerance = 1e-5;
    npf::AwlsReport pinned, drifting;
    npf::fit_npf(*source, o, &pinned);
    o.g_pin = 0.0;
    npf::fit_npf(*source, o, &drifting);
    std::printf("[ awls     ] ilm, 32 rows: %d sweeps pinned (error %.4e), %d without the pin (error %.4e); cap %d\n", pinned.iterations[0],
                pinned.relative_error[1], drifting.iterations[0], drifting.relative_error[1], o.max_iterations);
    EXPECT_LT(pinned.iterations[0], o.max_iterations / 2);
    EXPECT_EQ(drifting.iterations[0], o.max_iterations);
    for (std::size_t c = 0; c < 3; ++c) EXPECT_LT(pinned.relative_error[c], drifting.relative_error[c] * 1.05) << c;
}

// The line search that the paper preset keeps (and the fit used before Anderson's mix) also
// beats plain alternation after the same sweeps.
TEST(Awls, LineSearchBeatsPlainAlternation) {
    const AnalyticBrdf source(plastic(0.3f, 0.3f));
    npf::AwlsOptions o = isotropic_options(32, npf::Channels::spectral({550.f}));
    o.tolerance = 0.0;
    o.max_iterations = 60;
    o.g_pin = 0.0;
    npf::AwlsReport line, plain;
    o.acceleration = npf::AwlsOptions::Acceleration::LineSearch;
    npf::fit_npf(source, o, &line);
    o.acceleration = npf::AwlsOptions::Acceleration::None;
    npf::fit_npf(source, o, &plain);
    EXPECT_LT(line.relative_error[0], plain.relative_error[0]);
}

// A mirror-sharp lobe: the whole peak lies in the first few cells of the square-root grid.
// With w_I = (cos cos)^1 this fit was 4.8 % off with a diffuse albedo of 0.27 (docs/fitting.md);
// the default power 2 gets both right.
TEST(Awls, MirrorSharpLobeStaysFinite) {
    npf::AnalyticMaterial m = plastic(0.01f, 0.01f);
    const AnalyticBrdf source(m);
    const npf::AwlsOptions o = isotropic_options(90, npf::Channels::spectral({550.f}));
    const npf::NpfFactors f = npf::fit_npf(source, o);
    ASSERT_TRUE(all_finite(f));
    const double e = error_of(source, f, 5000).max_relative_rms;
    std::printf("[ awls     ] alpha 0.01: BRDF-space relative RMS %.2f %%, diffuse albedo %.3f (true 0.2)\n", 100.0 * e, f.rho_d[0] * npf::kPiD);
    EXPECT_LT(e, 0.03);
    EXPECT_NEAR(f.rho_d[0] * npf::kPiD, 0.1 + 0.2 * 150.0 / 300.0, 0.01);
    // The peak: D at the first cell as large as the true D there (~1 / (pi alpha^2)).
    EXPECT_GT(f.D[0], 0.5 / (npf::kPiD * 0.01 * 0.01));
}

TEST(Awls, PurelyDiffuseMaterialHasNoSpecular) {
    npf::AnalyticMaterial m;
    m.diffuse = npf::color::SampledSpectrum::constant(0.5);
    m.wavelengths = {550.f};
    const AnalyticBrdf source(m);
    const npf::NpfFactors f = npf::fit_npf(source, isotropic_options(32, npf::Channels::spectral({550.f})));
    ASSERT_TRUE(all_finite(f));
    EXPECT_NEAR(f.rho_d[0], 0.5 / npf::kPiD, 1e-4);
    EXPECT_LT(error_of(source, f).max_relative_rms, 1e-3);
}

// A source scaled by a constant, returning NaN where asked to: the data extremes.
class ScaledSource : public npf::Brdf {
public:
    ScaledSource(const npf::Brdf& base, float scale, bool nan_beyond_75 = false)
        : m_base(base), m_scale(scale), m_nan(nan_beyond_75) {}
    const npf::BrdfInfo& info() const override { return m_base.info(); }
    npf::ChannelQuery query(const npf::Channels& c) const override { return m_base.query(c); }
    void eval_cos(const npf::Vec3& wi, const npf::Vec3& wo, const npf::ChannelQuery& q, float* out) const override {
        m_base.eval_cos(wi, wo, q, out);
        for (std::size_t c = 0; c < q.size(); ++c) {
            out[c] *= m_scale;
            if (m_nan && wi.z < 0.25f) out[c] = std::numeric_limits<float>::quiet_NaN();
        }
    }
    float pdf(const npf::Vec3& wi, const npf::Vec3& wo) const override { return m_base.pdf(wi, wo); }
    bool sample(const npf::Vec3& wi, const npf::Vec2& u, const npf::ChannelQuery& q, npf::BrdfSample& s, float* w) const override {
        return m_base.sample(wi, u, q, s, w);
    }

private:
    const npf::Brdf& m_base;
    float m_scale;
    bool m_nan;
};

// Data that depend on the view direction alone (brighter towards a grazing wi): not
// reciprocal, so the model, whose G serves both directions, must compromise, and the split w_I
// decides for whom. At a pair and its swap the model gives one value; the side whose grazing
// direction is not down-weighted must win.
class ViewDependentSource : public npf::Brdf {
public:
    explicit ViewDependentSource(const npf::Brdf& base) : m_base(base) {}
    const npf::BrdfInfo& info() const override { return m_base.info(); }
    npf::ChannelQuery query(const npf::Channels& c) const override { return m_base.query(c); }
    void eval_cos(const npf::Vec3& wi, const npf::Vec3& wo, const npf::ChannelQuery& q, float* out) const override {
        m_base.eval_cos(wi, wo, q, out);
        for (std::size_t c = 0; c < q.size(); ++c) out[c] *= 1.f + 2.f * (1.f - wi.z);
    }
    float pdf(const npf::Vec3& wi, const npf::Vec3& wo) const override { return m_base.pdf(wi, wo); }
    bool sample(const npf::Vec3& wi, const npf::Vec2& u, const npf::ChannelQuery& q, npf::BrdfSample& s, float* w) const override {
        return m_base.sample(wi, u, q, s, w);
    }

private:
    const npf::Brdf& m_base;
};

TEST(Awls, ImportancePowersWeighViewAndLightSeparately) {
    npf::AnalyticMaterial m;
    m.diffuse = npf::color::SampledSpectrum::constant(0.5);
    m.wavelengths = {550.f};
    const AnalyticBrdf base(m);
    const ViewDependentSource source(base);
    const auto dir = [](double theta_deg, double phi) {
        const double t = theta_deg * npf::kPiD / 180.0;
        return Vec3d{std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t)};
    };
    const Vec3d grazing = dir(70.0, 0.0), steep = dir(20.0, npf::kPiD);
    const double data_grazing_view = 0.5 / npf::kPiD * (1.0 + 2.0 * (1.0 - grazing.z));  // f_r at (grazing, steep)
    const double data_steep_view = 0.5 / npf::kPiD * (1.0 + 2.0 * (1.0 - steep.z));      // and swapped
    const auto fitted = [&](double view, double light) {
        npf::AwlsOptions o = isotropic_options(24, npf::Channels::spectral({550.f}));
        o.importance_power_view = view;
        o.importance_power_light = light;
        const npf::NpfFactors f = npf::fit_npf(source, o);
        // The model is reciprocal here: the pair and its swap agree.
        EXPECT_NEAR(f.eval(0, grazing, steep), f.eval(0, steep, grazing), 1e-6);
        return f.eval(0, grazing, steep);
    };
    const double view_counts = fitted(0.0, 2.0), light_counts = fitted(2.0, 0.0);
    // Grazing views kept: the fit follows the (grazing view, steep light) data; and the reverse.
    EXPECT_LT(std::abs(view_counts - data_grazing_view), std::abs(light_counts - data_grazing_view));
    EXPECT_LT(std::abs(light_counts - data_steep_view), std::abs(view_counts - data_steep_view));
    EXPECT_GT(view_counts, 1.1 * light_counts);
}

// Partial sums are per slice of the samples, not per thread, and added in a fixed order: the
// factors are the same to the bit on 1, 2, 3 or 5 threads (batch outputs, farm and laptop).
TEST(Awls, TheFitDoesNotDependOnTheThreadCount) {
    const AnalyticBrdf source(plastic(0.15f, 0.3f));
    npf::AwlsOptions o;
    o.grid = {16, 8, 16, 16};
    o.g_theta = 16;
    o.g_phi = 8;
    o.channels = npf::Channels::spectral({450.f, 550.f, 650.f});
    o.max_iterations = 20;
    std::vector<npf::NpfFactors> fits;
    for (int threads : {1, 2, 3, 5}) {
        o.threads = threads;
        fits.push_back(npf::fit_npf(source, o));
    }
    for (std::size_t k = 1; k < fits.size(); ++k) {
        EXPECT_EQ(fits[k].D, fits[0].D) << k;
        EXPECT_EQ(fits[k].F, fits[0].F) << k;
        EXPECT_EQ(fits[k].G, fits[0].G) << k;
        EXPECT_EQ(fits[k].rho_d, fits[0].rho_d) << k;
        EXPECT_EQ(fits[k].rho_s, fits[0].rho_s) << k;
    }
}

// The passes over the samples are built for AVX2 and for any CPU (block_passes.h): the fit must
// not depend on which ran. Blocks of 4 lanes (three channels) and of 16 (20 wavelengths: a
// full block and a partial one).
TEST(Awls, TheFitIsTheSameOnEveryInstructionSet) {
    if (!npf::simd_isa_supported(npf::SimdIsa::Avx2)) GTEST_SKIP() << "this CPU has no AVX2";
    npf::AnalyticMaterial m = plastic(0.15f, 0.3f);
    for (int wavelengths : {3, 20}) {
        SCOPED_TRACE(wavelengths);
        m.wavelengths.clear();
        for (int k = 0; k < wavelengths; ++k) m.wavelengths.push_back(400.f + 300.f * float(k) / float(wavelengths - 1));
        const AnalyticBrdf source(m);
        npf::AwlsOptions o;
        o.grid = {16, 8, 16, 16};
        o.g_theta = 16;
        o.g_phi = 8;
        o.channels = npf::Channels::spectral(m.wavelengths);
        o.max_iterations = 12;
        std::vector<npf::NpfFactors> fits;
        for (npf::SimdIsa isa : {npf::SimdIsa::Portable, npf::SimdIsa::Avx2}) {
            const npf::SimdIsaScope scope(isa);
            fits.push_back(npf::fit_npf(source, o));
        }
        EXPECT_EQ(fits[1].D, fits[0].D);
        EXPECT_EQ(fits[1].F, fits[0].F);
        EXPECT_EQ(fits[1].G, fits[0].G);
        EXPECT_EQ(fits[1].rho_d, fits[0].rho_d);
        EXPECT_EQ(fits[1].rho_s, fits[0].rho_s);
    }
}

TEST(Awls, ZeroDataGiveZeroFactorsNotNaN) {
    const AnalyticBrdf base(plastic(0.2f, 0.2f));
    const ScaledSource zero(base, 0.f);
    const npf::NpfFactors f = npf::fit_npf(zero, isotropic_options(24, npf::Channels::spectral({550.f})));
    ASSERT_TRUE(all_finite(f));
    EXPECT_EQ(f.rho_d[0], 0.f);
    EXPECT_EQ(f.rho_s[0], 0.f);
}

// The fit is linear in the data's scale: rho_d and rho_s scale, D, F, G (in their gauge) do not.
// (Not with the compressive weight, whose epsilon is absolute, display-referred: at a scale of
// 1e-6 it is the plain weight. It is off here, so that the test sees the fit's own arithmetic.)
TEST(Awls, TinyAndHugeValuesScaleTheFit) {
    const AnalyticBrdf base(plastic(0.2f, 0.2f));
    npf::AwlsOptions o = isotropic_options(24, npf::Channels::spectral({550.f}));
    o.compressive_power = 0.0;
    const npf::NpfFactors unit = npf::fit_npf(base, o);
    for (float scale : {1e-6f, 1e4f}) {
        const ScaledSource scaled(base, scale);
        const npf::NpfFactors f = npf::fit_npf(scaled, o);
        ASSERT_TRUE(all_finite(f)) << scale;
        // Equal up to rounding, which the weakly constrained directions of the fit amplify a little.
        EXPECT_NEAR(f.rho_d[0] / scale, unit.rho_d[0], 5e-2 * unit.rho_d[0]) << scale;
        EXPECT_NEAR(f.rho_s[0] / scale, unit.rho_s[0], 5e-2 * unit.rho_s[0]) << scale;
        EXPECT_LT(error_of(scaled, f, 5000).max_relative_rms, 1.5 * error_of(base, unit, 5000).max_relative_rms + 1e-3) << scale;
    }
}

TEST(Awls, InvalidValuesAreLeftOutAndCounted) {
    const AnalyticBrdf base(plastic(0.2f, 0.2f));
    const ScaledSource holes(base, 1.f, true);
    npf::AwlsReport r;
    const npf::NpfFactors f = npf::fit_npf(holes, isotropic_options(24, npf::Channels::spectral({550.f})), &r);
    ASSERT_TRUE(all_finite(f));
    EXPECT_GT(r.invalid_values, 0u);
    EXPECT_LT(r.invalid_values, r.samples);
    const npf::NpfFactors whole = npf::fit_npf(base, isotropic_options(24, npf::Channels::spectral({550.f})));
    // Grazing wi lost (as in measurements with gaps there): the fit extrapolates, so allow some loss.
    EXPECT_LT(error_of(base, f, 5000).max_relative_rms, 3.0 * error_of(base, whole, 5000).max_relative_rms + 0.005);
}

// Many channels go through the blocked, lock-step path (16 lanes, warm starts between blocks):
// every channel must be fitted as well as by a fit of that channel alone.
TEST(Awls, BlocksOfChannelsFitAsWellAsSingleChannels) {
    npf::AnalyticMaterial m = plastic(0.25f, 0.25f);
    std::vector<float> wl;
    for (int k = 0; k < 20; ++k) wl.push_back(400.f + 15.f * float(k));
    m.wavelengths = wl;
    const AnalyticBrdf source(m);
    npf::AwlsOptions o = isotropic_options(24, npf::Channels::spectral(wl));
    const npf::NpfFactors all = npf::fit_npf(source, o);
    ASSERT_TRUE(all_finite(all));
    const npf::BrdfSpaceError e_all = error_of(source, all, 5000);
    for (std::size_t c : {std::size_t(0), std::size_t(15), std::size_t(16), std::size_t(19)}) {
        o.channels = npf::Channels::spectral({wl[c]});
        const npf::NpfFactors one = npf::fit_npf(source, o);
        const double e_one = error_of(source, one, 5000).max_relative_rms;
        std::printf("[ awls     ] channel %zu: %.3f %% in the block, %.3f %% alone\n", c, 100.0 * e_all.relative_rms[c], 100.0 * e_one);
        EXPECT_LT(e_all.relative_rms[c], 1.25 * e_one + 0.002) << "channel " << c;
    }
}

TEST(Awls, AnisotropicMaterialOnASubsampledGrid) {
    const AnalyticBrdf source(plastic(0.15f, 0.45f));
    npf::AwlsOptions o;
    o.grid = {24, 32, 24, 32};
    o.g_theta = 24;
    o.g_phi = 32;
    o.phi_d_samples = 8;
    o.channels = npf::Channels::spectral({550.f});
    npf::AwlsReport r;
    const npf::NpfFactors f = npf::fit_npf(source, o, &r);
    ASSERT_TRUE(all_finite(f));
    const double e = error_of(source, f, 5000).max_relative_rms;
    std::printf("[ awls     ] anisotropic 24x32x24 (8 phi_d samples): %zu samples, %d sweeps, BRDF-space relative RMS %.3f %%\n",
                r.samples, r.iterations[0], 100.0 * e);
    EXPECT_LT(e, 0.05);
}

TEST(Awls, RejectsBadOptions) {
    const AnalyticBrdf source(plastic(0.2f, 0.2f));
    npf::AwlsOptions o = isotropic_options(8, npf::Channels::spectral({550.f}));
    o.grid.theta_h = 1;
    EXPECT_THROW(npf::fit_npf(source, o), npf::Error);
    o = isotropic_options(8, npf::Channels::spectral({550.f}));
    o.compressive_epsilon = 0.0;
    EXPECT_THROW(npf::fit_npf(source, o), npf::Error);
    o = isotropic_options(8, npf::Channels::spectral({550.f}));
    o.max_iterations = 0;
    EXPECT_THROW(npf::fit_npf(source, o), npf::Error);
    for (double pin : {-1.0, double(NAN), double(INFINITY)}) {
        o = isotropic_options(8, npf::Channels::spectral({550.f}));
        o.g_pin = pin;
        EXPECT_THROW(npf::fit_npf(source, o), npf::Error) << pin;
    }
    o = isotropic_options(8, npf::Channels::spectral({550.f}));
    o.phi_d_samples = npf::awls_limits::kMaxPhiDSamples + 1;
    EXPECT_THROW(npf::fit_npf(source, o), npf::Error);
    o = isotropic_options(8, npf::Channels::spectral({550.f}));
    o.tolerance = -1e-3;
    EXPECT_THROW(npf::fit_npf(source, o), npf::Error);
}

// The fitter owns its bounds: the message says them, and the settings `npf convert` and the
// batch check take their ranges from the same declarations.
TEST(Awls, TheSettingsTakeTheFittersOwnBounds) {
    namespace lim = npf::awls_limits;
    const AnalyticBrdf source(plastic(0.2f, 0.2f));
    npf::AwlsOptions o = isotropic_options(8, npf::Channels::spectral({550.f}));
    o.grid.theta_d = lim::kMaxCells + 1;
    try {
        npf::fit_npf(source, o);
        ADD_FAILURE() << "a grid above the fitter's bound was fitted";
    } catch (const npf::Error& e) {
        EXPECT_EQ(std::string(e.what()), "fit: grid sizes must lie in 2..4096 (phi_h and the G phi cells from 1)");
    }
    const npf::ConvertSettingsTable& table = npf::convert_settings_table();
    const npf::ConvertSettingRow* grid = npf::find_setting(table, "grid");
    const npf::ConvertSettingRow* g_grid = npf::find_setting(table, "g_grid");
    ASSERT_TRUE(grid && g_grid);
    for (std::size_t axis = 0; axis < 4; ++axis) {
        EXPECT_EQ(grid->ranges.at(axis).low, axis == 1 ? lim::kMinPhiCells : lim::kMinCells) << axis;
        EXPECT_EQ(grid->ranges.at(axis).high, lim::kMaxCells) << axis;
    }
    EXPECT_EQ(g_grid->ranges.at(0).low, lim::kMinCells);
    EXPECT_EQ(g_grid->ranges.at(1).low, lim::kMinPhiCells);
    EXPECT_EQ(npf::find_setting(table, "phi_d_samples")->ranges.at(0).high, lim::kMaxPhiDSamples);
    EXPECT_EQ(npf::find_setting(table, "iterations")->ranges.at(0).high, lim::kMaxIterations);
}

}  // namespace
