// The Sphere scene renderer (npf/render/path_tracer.h): the furnace test, coverage and
// premultiplied alpha, determinism (seeds, thread counts), shared random numbers across
// materials, RGB against spectral rendering, MIS against either strategy alone, option errors.
#include "chi2.h"
#include "test_lambertian.h"

#include <npf/color/spectrum.h>
#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/core/error.h>
#include <npf/render/environment_map.h>
#include <npf/render/path_tracer.h>
#include <npf/render/render_channels.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

namespace {

using npf::Channels;
using npf::render::EnvironmentMap;
using npf::render::RenderOptions;
using npf::render::RenderResult;

constexpr double kPi = 3.14159265358979323846;

using npf::testing::Lambertian;

// An analytic glossy material (GGX lobe, Schlick-like Fresnel, diffuse), anisotropic.
std::unique_ptr<npf::AnalyticBrdf> glossy() {
    npf::AnalyticMaterial m;
    m.name = "glossy test material";
    npf::MicrofacetNdf ndf;
    ndf.alpha_x = 0.15f;
    ndf.alpha_y = 0.4f;
    m.specular.push_back(npf::SpecularLobe{ndf, npf::Fresnel::one(), npf::color::SampledSpectrum::constant(0.8)});
    m.diffuse = npf::color::SampledSpectrum::constant(0.2);
    m.wavelengths = {400.f, 500.f, 600.f, 700.f};
    return std::make_unique<npf::AnalyticBrdf>(m);
}

// A non-uniform map: dim sky gradient, a bright sun, a coloured patch.
EnvironmentMap test_map(bool grey = false) {
    const std::size_t w = 32, h = 16;
    std::vector<float> rgb(w * h * 3);
    for (std::size_t r = 0; r < h; ++r)
        for (std::size_t c = 0; c < w; ++c) {
            float* p = &rgb[(r * w + c) * 3];
            const float v = 0.1f + 0.4f * float(r) / float(h) + 0.2f * float(c % 7) / 7.f;
            p[0] = p[1] = p[2] = v;
            if (!grey && r > 10) p[0] = 1.5f * v, p[2] = 0.5f * v;
        }
    for (int k = 0; k < 3; ++k) rgb[(5 * w + 12) * 3 + std::size_t(k)] = 50.f;  // ahead-left, above the horizon
    return EnvironmentMap(w, h, std::move(rgb), grey ? "grey test map" : "test map");
}

RenderOptions small(std::size_t size, std::uint32_t spp, std::uint64_t seed = 1) {
    RenderOptions o;
    o.width = o.height = size;
    o.spp = spp;
    o.seed = seed;
    o.threads = 2;
    return o;
}

const float* pixel(const RenderResult& r, std::size_t x, std::size_t y) { return &r.image.pixels[(y * r.image.width + x) * 4]; }

bool same_bits(const RenderResult& a, const RenderResult& b) {
    return a.image.pixels.size() == b.image.pixels.size() &&
           std::memcmp(a.image.pixels.data(), b.image.pixels.data(), a.image.pixels.size() * sizeof(float)) == 0;
}

// Mean of channel c over the pixels with full coverage.
double interior_mean(const RenderResult& r, int c) {
    double sum = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < r.image.width * r.image.height; ++i)
        if (r.image.pixels[i * 4 + 3] == 1.f) sum += r.image.pixels[i * 4 + std::size_t(c)], ++n;
    return n ? sum / n : 0.0;
}

TEST(RenderPathTracer, FurnaceGivesAlbedoTimesRadiance) {
    // Constant radiance L from every direction on a Lambertian of albedo a: every fully covered
    // pixel converges to a L, whatever the strategy. Two maps: one texel (sampled uniformly in
    // (u, v), so denser at the poles) and 64 x 32 texels (nearly uniform in solid angle).
    const float a = 0.7f, L = 1.5f;
    const Lambertian lambert(a, Channels::rgb());
    const EnvironmentMap one = EnvironmentMap::constant(L, L, L);
    const EnvironmentMap many(64, 32, std::vector<float>(64 * 32 * 3, L), "constant 64x32");
    for (const EnvironmentMap* env : {&one, &many}) {
        const RenderResult r = npf::render::render(lambert, *env, small(16, 1024));
        int interior = 0;
        double worst = 0.0;
        for (std::size_t i = 0; i < 16 * 16; ++i) {
            const float* p = &r.image.pixels[i * 4];
            if (p[3] != 1.f) continue;
            ++interior;
            for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(p[c] / (a * L) - 1.0));
        }
        EXPECT_GT(interior, 100);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(interior_mean(r, c) / (a * L), 1.0, 1e-3) << env->source();
        EXPECT_LT(worst, 0.02) << env->source();
        EXPECT_EQ(r.stats.dropped_values, 0u);
    }
    // Each strategy alone converges to the same value.
    for (auto s : {npf::render::Sampling::Brdf, npf::render::Sampling::Environment}) {
        RenderOptions o = small(16, 1024);
        o.sampling = s;
        const RenderResult r = npf::render::render(lambert, many, o);
        EXPECT_NEAR(interior_mean(r, 1) / (a * L), 1.0, s == npf::render::Sampling::Brdf ? 1e-6 : 2e-3);
    }
}

TEST(RenderPathTracer, CoverageIsPremultipliedAlpha) {
    const Lambertian lambert(0.5f, Channels::rgb());
    const EnvironmentMap env = EnvironmentMap::constant(1.f, 1.f, 1.f);
    const std::size_t size = 64;
    const RenderResult r = npf::render::render(lambert, env, small(size, 64));
    ASSERT_EQ(r.image.channels, 4);
    ASSERT_EQ(r.image.width, size);
    ASSERT_EQ(r.image.pixels.size(), size * size * 4);
    // Corners: nothing at all.
    for (std::size_t c : {0, 1, 2, 3}) {
        EXPECT_EQ(pixel(r, 0, 0)[c], 0.f);
        EXPECT_EQ(pixel(r, size - 1, size - 1)[c], 0.f);
    }
    // Total coverage: the silhouette's area, a disc of radius 0.45 x the image height.
    double alpha = 0.0, rim_colour = 0.0, rim_alpha = 0.0;
    int partial = 0;
    for (std::size_t i = 0; i < size * size; ++i) {
        const float* p = &r.image.pixels[i * 4];
        alpha += p[3];
        if (p[3] > 0.f && p[3] < 1.f) {
            ++partial;
            rim_colour += p[1], rim_alpha += p[3];
        }
        EXPECT_LE(p[3], 1.f);
        if (p[3] == 0.f) {
            EXPECT_EQ(p[0] + p[1] + p[2], 0.f);
        }
    }
    // Premultiplied: on the rim, colour = alpha x the surface's value (0.5 here, up to noise).
    EXPECT_NEAR(rim_colour / rim_alpha, 0.5, 0.05);
    const double disc = kPi * std::pow(0.45 * double(size), 2.0);
    EXPECT_NEAR(alpha / disc, 1.0, 0.01);
    EXPECT_GT(partial, 100);  // the antialiased rim
    EXPECT_EQ(r.stats.camera_samples, size * size * 64u);
    EXPECT_NEAR(double(r.stats.hit_samples) / double(r.stats.camera_samples), disc / double(size * size), 0.005);
}

TEST(RenderPathTracer, SameSeedIsBitIdenticalForAnyThreadCount) {
    const auto material = glossy();
    const EnvironmentMap env = test_map();
    RenderOptions o = small(24, 8, 42);
    o.threads = 1;
    const RenderResult one = npf::render::render(*material, env, o);
    for (unsigned t : {1u, 2u, 3u, 7u}) {
        o.threads = t;
        const RenderResult again = npf::render::render(*material, env, o);
        EXPECT_TRUE(same_bits(one, again)) << t << " threads";
        EXPECT_EQ(again.stats.threads, t);
    }
}

TEST(RenderPathTracer, DifferentSeedsDifferButAgreeOnAverage) {
    const auto material = glossy();
    const EnvironmentMap env = test_map();
    const RenderResult a = npf::render::render(*material, env, small(32, 32, 1));
    const RenderResult b = npf::render::render(*material, env, small(32, 32, 2));
    EXPECT_FALSE(same_bits(a, b));
    int differ = 0;
    for (std::size_t i = 0; i < a.image.pixels.size(); i += 4) differ += a.image.pixels[i] != b.image.pixels[i];
    EXPECT_GT(differ, 500);
    for (int c = 0; c < 3; ++c) {
        const double ma = interior_mean(a, c), mb = interior_mean(b, c);
        EXPECT_GT(ma, 0.0);
        EXPECT_NEAR(ma / mb, 1.0, 0.02) << c;
    }
}

TEST(RenderPathTracer, MaterialsShareRandomNumbers) {
    // Albedos 0.5 and 0.25: every contribution halves exactly (a power of two), so with shared
    // random numbers the second image is exactly half the first, bit for bit.
    const EnvironmentMap env = test_map();
    const Lambertian half(0.5f, Channels::rgb()), quarter(0.25f, Channels::rgb());
    const RenderResult a = npf::render::render(half, env, small(24, 16, 9));
    const RenderResult b = npf::render::render(quarter, env, small(24, 16, 9));
    for (std::size_t i = 0; i < a.image.pixels.size(); ++i) {
        if (i % 4 == 3) {
            ASSERT_EQ(a.image.pixels[i], b.image.pixels[i]);
        } else {
            ASSERT_EQ(a.image.pixels[i] * 0.5f, b.image.pixels[i]) << i;
        }
    }
    // Any two materials see the same camera samples: identical coverage.
    const auto g = glossy();
    const RenderResult c = npf::render::render(*g, env, small(24, 16, 9));
    for (std::size_t i = 3; i < a.image.pixels.size(); i += 4) ASSERT_EQ(a.image.pixels[i], c.image.pixels[i]);
}

TEST(RenderPathTracer, MisAgreesWithEachStrategyAlone) {
    // A glossy anisotropic material under a map with a bright sun: BSDF sampling alone and
    // environment sampling alone are unbiased too, so all three converge to the same image.
    const auto material = glossy();
    const EnvironmentMap env = test_map();
    RenderOptions o = small(16, 512, 3);
    const RenderResult mis = npf::render::render(*material, env, o);
    o.sampling = npf::render::Sampling::Environment;
    const RenderResult light = npf::render::render(*material, env, o);
    o.sampling = npf::render::Sampling::Brdf;
    const RenderResult brdf = npf::render::render(*material, env, o);
    for (int c = 0; c < 3; ++c) {
        const double m = interior_mean(mis, c);
        EXPECT_NEAR(interior_mean(light, c) / m, 1.0, 0.02) << c;
        EXPECT_NEAR(interior_mean(brdf, c) / m, 1.0, 0.05) << c;
    }
}

TEST(RenderPathTracer, SpectralMatchesRgbForAFlatMaterialUnderAGreyMap) {
    // A white Lambertian once as an RGB material and once as a spectral one, under a grey map:
    // the spectral render integrates a flat spectrum, which comes out neutral (the D65 table's
    // white, (1.00016, 0.99998, 0.99976) of the RGB value, docs/color.md), with the same random
    // numbers, so pixel by pixel.
    const EnvironmentMap env = test_map(true);
    const Lambertian rgb(0.8f, Channels::rgb());
    const Lambertian spectral(0.8f, Channels::spectral(npf::parse_wavelength_list("360:830:48", "test")));
    const RenderResult a = npf::render::render(rgb, env, small(16, 16));
    const RenderResult b = npf::render::render(spectral, env, small(16, 16));
    EXPECT_TRUE(a.channels.is_rgb());
    ASSERT_FALSE(b.channels.is_rgb());
    EXPECT_EQ(b.channels.wavelengths().size(), 48u);
    const double white[3] = {1.00016, 0.99998, 0.99976};
    for (std::size_t i = 0; i < a.image.pixels.size(); i += 4) {
        EXPECT_EQ(a.image.pixels[i + 3], b.image.pixels[i + 3]);
        for (int c = 0; c < 3; ++c) {
            const double x = a.image.pixels[i + std::size_t(c)] * white[c], y = b.image.pixels[i + std::size_t(c)];
            EXPECT_NEAR(y, x, 2e-5 * x + 1e-7) << "pixel " << i / 4 << " channel " << c;
        }
        // Neutral.
        const float* p = &b.image.pixels[i];
        EXPECT_NEAR(p[0], p[1], 3e-4 * p[1] + 1e-7);
        EXPECT_NEAR(p[2], p[1], 3e-4 * p[1] + 1e-7);
    }
    // The same analytic material rendered as RGB and spectrally (its own 195 wavelengths).
    npf::AnalyticMaterial m;
    m.diffuse = npf::color::SampledSpectrum::constant(0.8);
    const npf::AnalyticBrdf analytic(m);
    ASSERT_FALSE(analytic.info().channels.is_rgb());
    const RenderResult s = npf::render::render(analytic, env, small(16, 16));
    RenderOptions as_rgb = small(16, 16);
    as_rgb.channels = Channels::rgb();
    const RenderResult r = npf::render::render(analytic, env, as_rgb);
    EXPECT_EQ(s.channels.wavelengths().size(), 195u);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(interior_mean(s, c) / interior_mean(r, c), 1.0, 1e-3) << c;

    // A coloured, glossy analytic material: under a grey map the spectral render is the colour of
    // the reflected spectrum, which is what the material's own RGB evaluation returns; the
    // material samples alike in both modes, so the images agree pixel by pixel.
    npf::AnalyticMaterial coloured;
    coloured.diffuse = npf::color::SampledSpectrum({400.0, 550.0, 700.0}, {0.05, 0.3, 0.7});
    npf::MicrofacetNdf ndf;
    ndf.alpha_x = 0.1f, ndf.alpha_y = 0.3f;
    coloured.specular.push_back(npf::SpecularLobe{ndf, npf::Fresnel::one(),
                                                  npf::color::SampledSpectrum({400.0, 700.0}, {0.2, 0.4})});
    const npf::AnalyticBrdf brdf(coloured);
    const RenderResult cs = npf::render::render(brdf, env, small(16, 16));
    const RenderResult cr = npf::render::render(brdf, env, as_rgb);
    double worst = 0.0;
    for (std::size_t i = 0; i < cs.image.pixels.size(); i += 4)
        for (int c = 0; c < 3; ++c) {
            const double x = cr.image.pixels[i + std::size_t(c)], y = cs.image.pixels[i + std::size_t(c)];
            worst = std::max(worst, std::fabs(y - x) / (std::fabs(x) + 1e-3));
        }
    EXPECT_LT(worst, 2e-3);
    const double red = interior_mean(cs, 0), blue = interior_mean(cs, 2);
    EXPECT_GT(std::fabs(red - blue), 0.2 * (red + blue));  // and it is coloured, not grey
}

TEST(RenderPathTracer, SpectralUpsamplingKeepsTheMapsColour) {
    // White Lambertian under a constant coloured map: the spectral render (map upsampled with the
    // sigmoid table, integrated against the CIE observer) returns the map's colour times the
    // albedo, to the table's accuracy (about 1e-3, docs/color.md).
    const Lambertian spectral(1.f, Channels::spectral(npf::parse_wavelength_list("360:830:95", "test")));
    for (const auto& c : {std::array<float, 3>{0.8f, 0.4f, 0.2f}, std::array<float, 3>{0.1f, 0.3f, 0.9f},
                          std::array<float, 3>{4.f, 4.f, 1.f}}) {
        const EnvironmentMap env = EnvironmentMap::constant(c[0], c[1], c[2]);
        RenderOptions o = small(8, 64);
        o.sampling = npf::render::Sampling::Brdf;  // exact for a Lambertian under a constant map
        const RenderResult r = npf::render::render(spectral, env, o);
        const float* p = pixel(r, 4, 4);
        ASSERT_EQ(p[3], 1.f);
        const double largest = std::max({c[0], c[1], c[2]});
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], c[std::size_t(k)], 4e-3 * largest) << k;
    }
}

TEST(RenderPathTracer, DefaultWavelengths) {
    // Enough stored wavelengths in 360..830 nm: as stored (all of them).
    const std::vector<float> many = npf::parse_wavelength_list("360:1000:195", "t");
    EXPECT_EQ(npf::render::default_render_wavelengths(Channels::spectral(many)), many);
    // Few: a 5 nm grid over 360..830 nm.
    const std::vector<float> grid = npf::render::default_render_wavelengths(Channels::spectral({400.f, 500.f, 600.f, 700.f}));
    ASSERT_EQ(grid.size(), 95u);
    EXPECT_EQ(grid.front(), 360.f);
    EXPECT_EQ(grid.back(), 830.f);
    // Requests are checked.
    const npf::BrdfInfo info;
    EXPECT_THROW(npf::render::choose_render_channels(info, Channels::spectral({500.f, 400.f})), npf::Error);
    EXPECT_THROW(npf::render::choose_render_channels(info, Channels::spectral({900.f, 1000.f})), npf::Error);
    EXPECT_TRUE(npf::render::choose_render_channels(info, std::nullopt).channels.is_rgb());
}

TEST(RenderPathTracer, BadOptionsAndChannelsThrow) {
    const Lambertian lambert(0.5f, Channels::rgb());
    const EnvironmentMap env = EnvironmentMap::constant(1.f, 1.f, 1.f);
    RenderOptions o = small(0, 4);
    EXPECT_THROW(npf::render::render(lambert, env, o), npf::Error);
    o = small(4, 0);
    EXPECT_THROW(npf::render::render(lambert, env, o), npf::Error);
    o = small(20000, 1);
    EXPECT_THROW(npf::render::render(lambert, env, o), npf::Error);
    // Wavelengths from an RGB material: Brdf::query refuses (here through the default query).
    struct RgbOnly : npf::Brdf {
        npf::BrdfInfo i;
        RgbOnly() { i.format = "rgb only"; }
        const npf::BrdfInfo& info() const override { return i; }
        void eval_cos(const npf::Vec3&, const npf::Vec3&, const npf::ChannelQuery& q, float* out) const override {
            for (std::size_t k = 0; k < q.size(); ++k) out[k] = 0.f;
        }
        float pdf(const npf::Vec3&, const npf::Vec3&) const override { return 0.f; }
        bool sample(const npf::Vec3&, const npf::Vec2&, const npf::ChannelQuery&, npf::BrdfSample&, float*) const override {
            return false;
        }
    } rgb_only;
    o = small(4, 1);
    o.channels = Channels::spectral({500.f, 600.f});
    EXPECT_THROW(npf::render::render(rgb_only, env, o), npf::Error);
}

TEST(RenderPathTracer, ProgressReachesOne) {
    const Lambertian lambert(0.5f, Channels::rgb());
    const EnvironmentMap env = EnvironmentMap::constant(1.f, 1.f, 1.f);
    std::vector<double> seen;
    npf::render::render(lambert, env, small(12, 1), [&](double f) { seen.push_back(f); });
    ASSERT_EQ(seen.size(), 12u);
    for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i], seen[i - 1]);
    EXPECT_DOUBLE_EQ(seen.back(), 1.0);
}

// Opt-in: the noise falls as 1 / sqrt(spp) (no bias floor): the RMS difference to a 4096 spp
// reference at 16, 64 and 256 spp.
TEST(SlowRenderPathTracer, NoiseFallsAsOneOverSqrtSpp) {
    const auto material = glossy();
    const EnvironmentMap env = test_map();
    const RenderResult ref = npf::render::render(*material, env, small(32, 4096, 100));
    double previous = 0.0;
    for (std::uint32_t spp : {16u, 64u, 256u}) {
        const RenderResult r = npf::render::render(*material, env, small(32, spp, 7));
        double sum = 0.0;
        for (std::size_t i = 0; i < r.image.pixels.size(); ++i)
            sum += std::pow(double(r.image.pixels[i]) - ref.image.pixels[i], 2.0);
        const double rms = std::sqrt(sum / double(r.image.pixels.size()));
        if (previous > 0.0) {
            EXPECT_NEAR(previous / rms, 2.0, 0.6) << spp;
        }
        previous = rms;
    }
}

}  // namespace
