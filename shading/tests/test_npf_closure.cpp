// The shading closure: the alias table and half-vector sampler it samples with, agreement of its
// two paths (memory, TextureSystem) with the converter's own evaluation of the factors, chi-square
// tests of its sampling on several materials, finite weights at grazing angles, and thread safety.

#include "chi2.h"
#include "npf_test_factors.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/fit/npf_factors.h>
#include <npf/fit/spectral_compression.h>
#include <npf/shading/npf_texture_file.h>
#include <npf/core/error.h>
#include <npf/shading/alias_table.h>
#include <npf/shading/half_vector_sampler.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_closure.h>
#include <npf/shading/table_interpolation.h>

#include <OpenImageIO/texture.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace {

using npf::ClosureSample, npf::NpfClosure, npf::NpfFactors, npf::NpfModel, npf::Vec3, npf::WavelengthRequest,
      npf::testing::make_microfacet_factors, npf::testing::make_test_factors, npf::testing::MicrofacetSpec,
      npf::testing::Pcg32;

const std::string& folder() {
    static const std::string dir = npf::testing::temporary_folder("npf-closure");
    return dir;
}

std::string file(const std::string& name) { return folder() + "/" + name; }

NpfModel full_rank(const NpfFactors& f) { return npf::compress_factors(f, npf::CompressionOptions()); }

Vec3 direction(double theta, double phi) {
    return {float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta))};
}

Vec3 random_direction(std::mt19937& rng) {
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const double z = 0.02 + 0.98 * uni(rng), phi = 2.0 * npf::kPiD * uni(rng), r = std::sqrt(1.0 - z * z);
    return {float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)};
}

npf::Vec3d to_double(const Vec3& v) { return {v.x, v.y, v.z}; }

// ---- Fast angles -----------------------------------------------------------------------------

// The shading path's atan2 (npf/shading/table_interpolation.h) against std::atan2, in every
// quadrant, at the axes and across magnitudes.
TEST(TableAngles, Atan2MatchesTheStandardOne) {
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    double worst = 0.0;
    for (int n = 0; n < 1000000; ++n) {
        const double scale = std::pow(10.0, 6.0 * uni(rng));
        const double y = uni(rng) * scale, x = uni(rng);
        worst = std::max(worst, std::fabs(npf::table::atan2(y, x) - std::atan2(y, x)));
    }
    // The polynomial's own error is 2e-13 rad; a whole table cell is at least 4e-3 rad.
    EXPECT_LT(worst, 3e-13);
    EXPECT_GT(worst, 0.0);  // not std::atan2 under another name
    for (double y : {0.0, 1.0, -1.0, 1e-300, -1e-300, 1e300}) {
        for (double x : {0.0, 1.0, -1.0, 1e-300, -1e-300, 1e300}) {
            if (x == 0.0 && y == 0.0) continue;
            EXPECT_NEAR(npf::table::atan2(y, x), std::atan2(y, x), 3e-13) << y << ", " << x;
        }
    }
    EXPECT_EQ(npf::table::atan2(0.0, 0.0), 0.0);
    // polar_of(r, z) is atan2(r, z) over the whole range of z, the lower hemisphere included.
    for (int n = 0; n < 100000; ++n) {
        const double r = std::fabs(uni(rng)), z = uni(rng);
        ASSERT_NEAR(npf::table::polar_of(r, z), std::atan2(r, z), 3e-13) << r << ", " << z;
    }
    EXPECT_NEAR(npf::table::polar(0.0, 0.0, 1.0), 0.0, 1e-300);
    EXPECT_NEAR(npf::table::polar(1e-9, 0.0, 1.0), 1e-9, 1e-24);  // the pole keeps its digits
    EXPECT_NEAR(npf::table::polar(1.0, 0.0, -1e-9), 0.5 * npf::kPiD + 1e-9, 1e-15);
    EXPECT_NEAR(npf::table::azimuth(1.0, -1e-12), 2.0 * npf::kPiD - 1e-12, 1e-15);
    EXPECT_DOUBLE_EQ(npf::table::azimuth(0.0, -1.0), 1.5 * npf::kPiD);
}

// ---- Wavelength location -------------------------------------------------------------------

// How headers and messages name a channel (npf albedo's columns, npf convert's energy line).
TEST(Channels, NamesRgbAndWavelengthChannels) {
    const npf::Channels rgb = npf::Channels::rgb();
    EXPECT_EQ(rgb.name(0), "R");
    EXPECT_EQ(rgb.name(1), "G");
    EXPECT_EQ(rgb.name(2), "B");
    const npf::Channels spectral = npf::Channels::spectral({450.f, 552.5f});
    EXPECT_EQ(spectral.name(0), "450nm");
    EXPECT_EQ(spectral.name(1), "552.5nm");
    EXPECT_THROW(spectral.name(2), std::out_of_range);
}

TEST(WavelengthLocator, AgreesWithTheSearchToTheBit) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    std::vector<std::vector<float>> grids;
    std::vector<float> uniform, uneven, clustered;
    for (int k = 0; k < 195; ++k) uniform.push_back(360.f + 2.4f * float(k));
    float w = 300.f;
    for (int k = 0; k < 60; ++k) uneven.push_back(w += 0.01f + 20.f * uni(rng) * uni(rng));
    for (int k = 0; k < 40; ++k) clustered.push_back(k < 30 ? 500.f + 0.001f * float(k) : 500.f + 100.f * float(k));
    grids = {uniform, uneven, clustered, {550.f}, {400.f, 700.f}, {450.f, 450.f, 600.f}};
    for (const std::vector<float>& grid : grids) {
        const npf::WavelengthLocator locator(grid);
        std::vector<float> queries = {std::nanf(""), std::numeric_limits<float>::infinity(),
                                      -std::numeric_limits<float>::infinity(), 0.f, 1e30f};
        for (float g : grid) {
            queries.push_back(g);
            queries.push_back(std::nextafter(g, 0.f));
            queries.push_back(std::nextafter(g, 1e30f));
        }
        const float lo = grid.front() - 50.f, span = grid.back() - grid.front() + 100.f;
        for (int n = 0; n < 20000; ++n) queries.push_back(lo + span * uni(rng));
        for (float lambda : queries) {
            std::uint32_t a0, a1, b0, b1;
            float ta, tb;
            npf::locate_wavelength(grid.data(), grid.size(), lambda, a0, a1, ta);
            locator.locate(lambda, b0, b1, tb);
            ASSERT_EQ(a0, b0) << lambda << " on a grid of " << grid.size();
            ASSERT_EQ(a1, b1) << lambda;
            if (std::isnan(ta)) {
                ASSERT_TRUE(std::isnan(tb)) << lambda;
            } else {
                ASSERT_EQ(ta, tb) << lambda;
            }
        }
    }
}

// ---- Alias table ---------------------------------------------------------------------------

TEST(AliasTable, DrawsEachIndexWithItsProbability) {
    const std::vector<double> w = {0.0, 1.0, 2.0, 3.0, 0.0, 10.0, 0.5, 1e-3, 7.0, 0.0};
    const npf::AliasTable table(w);
    double sum = 0.0;
    for (double v : w) sum += v;
    constexpr int kDraws = 2000000;
    std::vector<int> count(w.size(), 0);
    std::vector<int> remainder_bins(10, 0);
    Pcg32 rng(3);
    for (int n = 0; n < kDraws; ++n) {
        const npf::AliasTable::Draw d = table.sample(rng.next_float());
        ASSERT_LT(d.index, w.size());
        ASSERT_GE(d.remainder, 0.f);
        ASSERT_LT(d.remainder, 1.f);
        ++count[d.index];
        ++remainder_bins[std::size_t(d.remainder * 10.f)];
    }
    for (std::size_t i = 0; i < w.size(); ++i) {
        const double p = w[i] / sum, expected = p * kDraws, sigma = std::sqrt(kDraws * p * (1 - p));
        EXPECT_NEAR(table.pmf(i), p, 1e-7);
        if (w[i] == 0.0) {
            EXPECT_EQ(count[i], 0) << "index " << i << " has no weight";
        } else {
            EXPECT_NEAR(count[i], expected, 5.0 * sigma + 1.0) << "index " << i;
        }
    }
    // What is left of u is uniform, so the caller can use it for the next dimension.
    for (int b : remainder_bins) EXPECT_NEAR(b, kDraws / 10.0, 5.0 * std::sqrt(kDraws * 0.09));
}

TEST(AliasTable, RejectsWeightsItCannotDrawFrom) {
    EXPECT_THROW(npf::AliasTable(std::vector<double>{}), npf::Error);
    EXPECT_THROW(npf::AliasTable(std::vector<double>{0.0, 0.0}), npf::Error);
    EXPECT_THROW(npf::AliasTable(std::vector<double>{1.0, -1.0}), npf::Error);
    EXPECT_THROW(npf::AliasTable(std::vector<double>{1.0, std::nan("")}), npf::Error);
    EXPECT_THROW(npf::AliasTable(std::vector<double>{1.0, HUGE_VAL}), npf::Error);
    // One index: always drawn, u passed through.
    const npf::AliasTable one(std::vector<double>{2.0});
    EXPECT_EQ(one.sample(0.7f).index, 0u);
    EXPECT_NEAR(one.sample(0.7f).remainder, 0.7f, 1e-6f);
}

// ---- Half-vector sampler -------------------------------------------------------------------

// The density integrates to 1 over the hemisphere (midpoint rule in cos theta and phi, fine
// enough to resolve the sqrt-mapped cells), and sampled half vectors land where it says.
TEST(HalfVectorSampler, DensityIntegratesToOneAndMatchesItsSamples) {
    const NpfFactors f = make_microfacet_factors({0.15, 0.4, 0.0, 1.0, 3, false, 24, 16, 8, 8, 8});
    const NpfModel m = full_rank(f);
    const npf::HalfVectorSampler s(npf::HalfVectorSampler::luminance_averaged_ndf(m), m.d_theta, m.d_phi);
    double integral = 0.0;
    constexpr int kRows = 4000, kCols = 64;
    for (int i = 0; i < kRows; ++i) {
        const double z = (i + 0.5) / kRows, r = std::sqrt(1.0 - z * z);
        for (int j = 0; j < kCols; ++j) {
            const double phi = 2.0 * npf::kPiD * (j + 0.5) / kCols;
            integral += s.pdf(Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)));
        }
    }
    integral *= 2.0 * npf::kPiD / (double(kRows) * kCols);
    EXPECT_NEAR(integral, 1.0, 2e-3);

    // The projected-area NDF (D cos, integral 1) and the sampler's density agree on average:
    // E_h~pdf[D(h) cos(theta_h) / pdf(h)] = integral D cos = 1.
    Pcg32 rng(11);
    double mean = 0.0;
    constexpr int kSamples = 200000;
    for (int n = 0; n < kSamples; ++n) {
        const Vec3 h = s.sample(rng.next_float(), rng.next_float());
        ASSERT_GT(h.z, 0.f);
        ASSERT_NEAR(npf::length(h), 1.f, 1e-5f);
        const double pdf = s.pdf(h);
        ASSERT_GT(pdf, 0.0);
        const double ax = 0.15, ay = 0.4, t2 = (h.x * h.x + h.y * h.y) / (h.z * h.z);
        const double e = (h.x * h.x / (ax * ax) + h.y * h.y / (ay * ay)) / (h.x * h.x + h.y * h.y + 1e-30) * t2;
        const double d = 1.0 / (npf::kPiD * ax * ay * std::pow(h.z, 4.0) * (1 + e) * (1 + e));
        mean += d * h.z / pdf;
    }
    EXPECT_NEAR(mean / kSamples, 1.0, 0.03);
}

// ---- Agreement with the converter's evaluation ---------------------------------------------

struct AgreementCase {
    const char* name;
    NpfFactors factors;
};

std::vector<AgreementCase> agreement_cases() {
    return {
        {"rgb_isotropic", make_test_factors({false, 3, false, 4})},
        {"spectral_anisotropic", make_test_factors({true, 20, true, 5})},
        {"microfacet_spectral_anisotropic",
         make_microfacet_factors({0.1, 0.35, 0.05, 1.5, 12, true, 32, 64, 32, 32, 48})},
        {"sharp_isotropic", make_microfacet_factors({0.02, 0.02, 0.0, 1.0, 3, false, 90, 1, 90, 90, 1})},
    };
}

// Both paths give the converter's own evaluation of the factors (NpfFactors::eval, full rank) to
// 1e-5 relative, for the stored channels and for wavelengths between them.
TEST(NpfClosure, BothPathsMatchTheConvertersEvaluation) {
    for (const AgreementCase& c : agreement_cases()) {
        SCOPED_TRACE(c.name);
        const NpfFactors& f = c.factors;
        const std::string path = file(std::string(c.name) + ".exr");
        npf::write_npf_texture(full_rank(f), path);
        const NpfClosure memory(path, NpfClosure::Path::Memory);
        const NpfClosure texture(path, NpfClosure::Path::Texture);
        EXPECT_TRUE(texture.model().D.basis.empty()) << "the texture path keeps D in the TextureSystem only";
        const std::size_t C = f.channel_count();
        std::vector<float> a(C), b(C);
        std::mt19937 rng(9);
        double worst = 0.0;
        for (int n = 0; n < 3000; ++n) {
            // Half of the pairs near the specular peak, where D varies fastest.
            const Vec3 wo = random_direction(rng);
            Vec3 wi = random_direction(rng);
            if (n % 2) {
                const Vec3 mirror(-wo.x, -wo.y, wo.z);
                const Vec3 jitter = random_direction(rng);
                wi = npf::normalize(Vec3(mirror.x + 0.05f * jitter.x, mirror.y + 0.05f * jitter.y, mirror.z));
            }
            const float pa = memory.eval(wo, wi, WavelengthRequest::stored(), a.data());
            const float pb = texture.eval(wo, wi, WavelengthRequest::stored(), b.data());
            ASSERT_EQ(pa, pb) << "the pdf does not depend on the path";
            for (std::size_t ch = 0; ch < C; ++ch) {
                const double want = f.eval(ch, to_double(wo), to_double(wi)) * wi.z;
                const double tolerance = 1e-5 * std::fabs(want) + 1e-7;
                ASSERT_NEAR(a[ch], want, tolerance) << "memory path, channel " << ch << " pair " << n;
                ASSERT_NEAR(b[ch], want, tolerance) << "texture path, channel " << ch << " pair " << n;
                if (want > 1e-3) worst = std::max(worst, std::fabs(b[ch] - want) / want);
            }
        }
        std::printf("[ figures  ] %s: worst texture-path relative difference %.2e\n", c.name, worst);
        if (f.channels.is_rgb()) continue;
        // Hero wavelengths, anywhere in (and beyond) the stored range: linear between the stored ones.
        const std::vector<float>& grid = f.channels.wavelengths();
        for (int n = 0; n < 500; ++n) {
            const Vec3 wo = random_direction(rng), wi = random_direction(rng);
            std::uniform_real_distribution<float> lambda(grid.front() - 20.f, grid.back() + 20.f);
            const float hero[4] = {lambda(rng), lambda(rng), lambda(rng), grid[1]};
            float va[4], vb[4];
            memory.eval(wo, wi, WavelengthRequest::at(hero, 4), va);
            texture.eval(wo, wi, WavelengthRequest::at(hero, 4), vb);
            for (int k = 0; k < 4; ++k) {
                std::uint32_t i0, i1;
                float t;
                npf::locate_wavelength(grid.data(), grid.size(), hero[k], i0, i1, t);
                const double want = ((1 - t) * f.eval(i0, to_double(wo), to_double(wi)) +
                                     t * f.eval(i1, to_double(wo), to_double(wi))) * wi.z;
                ASSERT_NEAR(va[k], want, 1e-5 * std::fabs(want) + 1e-7) << "lambda " << hero[k];
                ASSERT_NEAR(vb[k], want, 1e-5 * std::fabs(want) + 1e-7) << "lambda " << hero[k];
            }
        }
    }
}

// A host's own TextureSystem serves the lookups; the closure leaves it alive.
TEST(NpfClosure, ShadesThroughTheHostsTextureSystem) {
    const NpfFactors f = make_test_factors({true, 6, true, 8});
    const std::string path = file("host.exr");
    npf::write_npf_texture(full_rank(f), path);
    OIIO::TextureSystem* ts = OIIO::TextureSystem::create(/*shared=*/false);
    {
        const NpfClosure closure(path, NpfClosure::Path::Texture, ts);
        const NpfClosure memory(path);
        float a[6], b[6];
        const Vec3 wo = direction(0.4, 0.3), wi = direction(0.5, 3.0);
        closure.eval(wo, wi, WavelengthRequest::stored(), a);
        memory.eval(wo, wi, WavelengthRequest::stored(), b);
        for (int c = 0; c < 6; ++c) EXPECT_NEAR(a[c], b[c], 1e-5 * b[c]);
    }
    int subimages = 0;
    EXPECT_TRUE(ts->get_texture_info(OIIO::ustring(path), 0, OIIO::ustring("subimages"), OIIO::TypeInt, &subimages));
    EXPECT_EQ(subimages, 4);
    OIIO::TextureSystem::destroy(ts);
}

TEST(NpfClosure, OpeningErrorsNameTheFile) {
    for (NpfClosure::Path p : {NpfClosure::Path::Memory, NpfClosure::Path::Texture}) {
        const std::string missing = file("no such file.exr");
        try {
            NpfClosure c(missing, p);
            ADD_FAILURE() << "opened a missing file";
        } catch (const npf::Error& e) {
            EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
        }
        // A valid texture cut short: its pixels are missing, on the TextureSystem's route too.
        const std::string whole = file("whole.exr"), cut = file("cut short.exr");
        npf::write_npf_texture(full_rank(make_test_factors({true, 6, true, 8})), whole);
        {
            std::ifstream in(whole, std::ios::binary);
            const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
        }
        try {
            NpfClosure c(cut, p);
            ADD_FAILURE() << "opened a truncated file";
        } catch (const npf::Error& e) {
            EXPECT_NE(std::string(e.what()).find(cut), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("truncated or corrupt"), std::string::npos) << e.what();
        }
        const std::string junk = file("junk.exr");
        std::ofstream(junk) << "not an image";
        try {
            NpfClosure c(junk, p);
            ADD_FAILURE() << "opened a text file";
        } catch (const npf::Error& e) {
            EXPECT_NE(std::string(e.what()).find("junk.exr"), std::string::npos) << e.what();
        }
    }
}

TEST(NpfClosure, RgbMaterialsShadeInRgbAndTheHorizonIsBlack) {
    const NpfClosure c(full_rank(make_test_factors({false, 3, false, 2})));
    const float hero[4] = {450.f, 500.f, 550.f, 600.f};
    EXPECT_EQ(c.value_count(WavelengthRequest::at(hero, 4)), 3u);
    EXPECT_EQ(c.value_count(WavelengthRequest::stored()), 3u);
    float v[3] = {1.f, 1.f, 1.f};
    EXPECT_EQ(c.eval(direction(0.3, 0.0), Vec3(0.6f, 0.f, -0.8f), WavelengthRequest::stored(), v), 0.f);
    for (float x : v) EXPECT_EQ(x, 0.f);
    EXPECT_EQ(c.pdf(Vec3(0.f, 0.6f, -0.8f), direction(0.3, 0.0)), 0.f);
    ClosureSample s;
    EXPECT_FALSE(c.sample(Vec3(0.f, 0.f, -1.f), 0.5f, 0.5f, WavelengthRequest::stored(), s, v));
}

// A material without a specular term samples cosine-weighted only; one without diffuse only
// through the half vector.
TEST(NpfClosure, StrategiesFollowTheAlbedos) {
    NpfFactors diffuse = make_microfacet_factors({0.3, 0.3, 0.4, 1.0, 3, false, 16, 1, 16, 16, 1});
    for (float& r : diffuse.rho_s) r = 0.f;
    EXPECT_EQ(NpfClosure(full_rank(diffuse)).diffuse_probability(), 1.0);
    const NpfFactors metal = make_microfacet_factors({0.3, 0.3, 0.0, 1.0, 3, false, 16, 1, 16, 16, 1});
    EXPECT_EQ(NpfClosure(full_rank(metal)).diffuse_probability(), 0.0);
    const NpfFactors both = make_microfacet_factors({0.3, 0.3, 0.2, 0.3, 3, false, 16, 1, 16, 16, 1});
    const double p = NpfClosure(full_rank(both)).diffuse_probability();
    EXPECT_GT(p, 0.05);
    EXPECT_LT(p, 0.95);
}

// ---- Sampling ------------------------------------------------------------------------------

struct SamplingCase {
    const char* name;
    MicrofacetSpec spec;
};

// Chi-square tests of sample() against pdf() (through NpfBrdf, the npf::Brdf view of the closure
// that the test harness drives) for rough, sharp, anisotropic, diffuse-heavy and spectral
// materials, at normal, oblique and grazing incidence; pdf integrates to 1 less what falls below
// the horizon; every weight is finite.
TEST(NpfClosure, SamplingPassesChiSquare) {
    const SamplingCase cases[] = {
        {"rough isotropic", {0.5, 0.5, 0.1, 1.0, 3, false, 32, 1, 32, 32, 1}},
        {"sharp isotropic", {0.03, 0.03, 0.0, 1.0, 3, false, 90, 1, 90, 90, 1}},
        {"anisotropic", {0.08, 0.35, 0.05, 1.0, 3, false, 32, 64, 32, 32, 32}},
        {"diffuse heavy", {0.3, 0.3, 0.6, 0.2, 3, false, 32, 1, 32, 32, 1}},
        {"spectral anisotropic", {0.2, 0.06, 0.1, 1.0, 8, true, 32, 48, 32, 24, 24}},
    };
    const double thetas[] = {0.0, 0.7, 1.2, 1.5};
    const int trials = int(std::size(cases) * std::size(thetas));
    for (const SamplingCase& c : cases) {
        const NpfFactors f = make_microfacet_factors(c.spec);
        const npf::NpfBrdf brdf(full_rank(f));
        const npf::ChannelQuery q = brdf.native_query();
        for (double theta : thetas) {
            SCOPED_TRACE(std::string(c.name) + ", theta_i " + std::to_string(theta));
            npf::testing::Chi2Options opt;
            opt.sample_count = 400000;
            opt.cos_theta_bins = 16;
            opt.phi_bins = 32;
            opt.trials = trials;
            opt.query = &q;
            opt.integration_resolution = 24;  // 10 leaves 0.3 % quadrature error on the spectral lobe
            const npf::testing::Chi2Result r = npf::testing::run_chi2_test(brdf, direction(theta, 0.6), opt);
            EXPECT_TRUE(r.passed) << r.message;
            EXPECT_EQ(r.invalid_samples, 0u);
            EXPECT_LE(r.pdf_integral, 1.0 + 5e-3);
            // Seen from the normal, a sharp lobe loses nothing below the horizon: the density
            // integrates to 1. (Elsewhere the harness checks that the samples that fail are
            // exactly the missing mass.)
            if (theta == 0.0 && c.spec.alpha_x < 0.05) {
                EXPECT_NEAR(r.pdf_integral, 1.0, 5e-3);  // GGX loses 0.1 %, the quadrature 0.2 %
            }
        }
    }
}

// Weights stay finite however close to the horizon the view is, and however the random
// numbers fall.
TEST(NpfClosure, WeightsAreFiniteAtGrazingViews) {
    const NpfFactors f = make_microfacet_factors({0.05, 0.2, 0.1, 2.0, 6, true, 32, 32, 32, 32, 32});
    const NpfClosure c(full_rank(f));
    Pcg32 rng(5);
    const float hero[4] = {420.f, 510.f, 600.f, 690.f};
    int accepted = 0;
    for (double z : {0.3, 0.05, 1e-3, 1e-5, 1e-7, 1e-20, 1e-38}) {
        const double r = std::sqrt(1.0 - z * z);
        const Vec3 wo(float(r * 0.6), float(r * 0.8), float(z));
        for (int n = 0; n < 20000; ++n) {
            ClosureSample s;
            float w[4];
            const float u1 = n < 4 ? (n % 2 ? 0.f : 0x1.fffffep-1f) : rng.next_float();
            const float u2 = n < 4 ? (n / 2 ? 0.f : 0x1.fffffep-1f) : rng.next_float();
            if (!c.sample(wo, u1, u2, WavelengthRequest::at(hero, 4), s, w)) {
                for (float x : w) ASSERT_EQ(x, 0.f);
                continue;
            }
            ++accepted;
            ASSERT_GT(s.pdf, 0.f);
            ASSERT_TRUE(std::isfinite(s.pdf));
            ASSERT_GT(s.light.z, 0.f);
            for (float x : w) {
                ASSERT_TRUE(std::isfinite(x)) << "wo.z " << z;
                ASSERT_GE(x, 0.f);
            }
        }
    }
    EXPECT_GT(accepted, 50000);
}

// ---- Threads -------------------------------------------------------------------------------

// Many threads shading one closure at once (each path) get exactly what one thread gets.
TEST(NpfClosure, ThreadsShadeAlike) {
    const NpfFactors f = make_microfacet_factors({0.1, 0.3, 0.05, 1.0, 10, true, 32, 32, 32, 32, 32});
    const std::string path = file("threads.exr");
    npf::write_npf_texture(full_rank(f), path);
    for (NpfClosure::Path p : {NpfClosure::Path::Memory, NpfClosure::Path::Texture}) {
        const NpfClosure c(path, p);
        constexpr int kPairs = 4000;
        auto run = [&](std::vector<float>& out) {
            std::mt19937 rng(21);
            Pcg32 u(77);
            const float hero[4] = {430.f, 520.f, 610.f, 695.f};
            out.clear();
            for (int n = 0; n < kPairs; ++n) {
                const Vec3 wo = random_direction(rng), wi = random_direction(rng);
                float v[4];
                out.push_back(c.eval(wo, wi, WavelengthRequest::at(hero, 4), v));
                out.insert(out.end(), v, v + 4);
                ClosureSample s;
                c.sample(wo, u.next_float(), u.next_float(), WavelengthRequest::at(hero, 4), s, v);
                out.insert(out.end(), {s.light.x, s.light.y, s.light.z, s.pdf});
                out.insert(out.end(), v, v + 4);
            }
        };
        std::vector<float> reference;
        run(reference);
        constexpr int kThreads = 8;
        std::vector<std::vector<float>> results(kThreads);
        std::vector<std::thread> threads;
        for (int t = 0; t < kThreads; ++t) threads.emplace_back([&, t] { run(results[std::size_t(t)]); });
        for (std::thread& t : threads) t.join();
        for (int t = 0; t < kThreads; ++t) {
            ASSERT_EQ(results[std::size_t(t)].size(), reference.size());
            EXPECT_EQ(0, std::memcmp(results[std::size_t(t)].data(), reference.data(), reference.size() * sizeof(float)))
                << "thread " << t << (p == NpfClosure::Path::Texture ? " (texture path)" : " (memory path)");
        }
    }
}

}  // namespace
