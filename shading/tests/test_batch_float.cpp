// The batched closure's float lanes (BatchPrecision::Float, npf/shading/npf_batch.h) against its
// double path, held to the float budget of docs/shading.md: the BRDF-space relative RMS of the
// difference (compare_brdfs' measure, npf/core/brdf_comparison.h) at the shared reference pairs
// and the held-out pairs at most 1e-4 (eval_batch's pdfs likewise), and a paired render (delta lights on the Sphere, no Monte
// Carlo: every pixel difference is the eval's) at 80 dB or more. Materials: the repository's
// shipped RGB factor texture with a detail layer, and an analytic anisotropic spectral one with a
// detail layer whose residual reaches the clamp.
#include "batched_brdf.h"
#include "npf_test_factors.h"
#include "synthetic_rgl.h"

#include <npf/fit/spectral_compression.h>
#include <npf/core/brdf_comparison.h>
#include <npf/core/simd_isa.h>
#include <npf/render/image_metrics.h>
#include <npf/render/lighting.h>
#include <npf/shading/npf_batch.h>
#include <npf/shading/npf_closure.h>
#include <npf/shading/npf_texture_file.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using npf::BatchPrecision;
using npf::BatchWavelengths;
using npf::DirectionPair;
using npf::NpfClosure;
using npf::Vec3;

constexpr double kBudgetRelativeRms = 1e-4;  // docs/shading.md, "The float budget"
constexpr double kBudgetPsnr = 80.0;

// The shared reference pairs (../shared/data/rgl/reference/dirs.txt; empty where absent) and the
// held-out pairs every conversion is measured at.
std::vector<DirectionPair> reference_pairs() {
    std::vector<DirectionPair> pairs = npf::held_out_pairs();
    const std::string dirs = npf::testing::shared_data_file("rgl/reference/dirs.txt");
    if (dirs.empty()) return pairs;
    std::ifstream in(dirs);
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        DirectionPair p;
        if (s >> p.wi.x >> p.wi.y >> p.wi.z >> p.wo.x >> p.wo.y >> p.wo.z) pairs.push_back(p);
    }
    return pairs;
}

// Every value of eval_batch at `pairs` (view = wi, light = wo), pair-major: pair i's value k at
// [i * count + k].
std::vector<float> batch_values(const NpfClosure& c, const std::vector<DirectionPair>& pairs, BatchWavelengths wl,
                                std::size_t count, std::vector<float>* pdf_out = nullptr) {
    const std::size_t n = pairs.size();
    std::vector<float> a[6];
    for (const DirectionPair& p : pairs) {
        const float v[6] = {p.wi.x, p.wi.y, p.wi.z, p.wo.x, p.wo.y, p.wo.z};
        for (int k = 0; k < 6; ++k) a[k].push_back(v[k]);
    }
    std::vector<float> channel_major(n * count), pdf(n), out(n * count);
    c.eval_batch(n, {a[0].data(), a[1].data(), a[2].data()}, {a[3].data(), a[4].data(), a[5].data()}, wl,
                 channel_major.data(), pdf.data());
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < count; ++k) out[i * count + k] = channel_major[k * n + i];
    if (pdf_out) *pdf_out = pdf;
    return out;
}

struct FloatAgainstDouble {
    npf::BrdfComparisonResult comparison;
    double pdf_relative_rms = 0.0;  // eval_batch's pdfs, the same measure over all pairs
    std::size_t differing = 0;  // values not equal to the bit (0: the float lanes did not run)
};

FloatAgainstDouble compare_precisions(const std::string& path, BatchWavelengths wl, std::size_t count,
                                      const std::vector<DirectionPair>& pairs) {
    NpfClosure doubles(path), floats(path);
    floats.set_batch_precision(BatchPrecision::Float);
    std::vector<float> pdf_d, pdf_f;
    const std::vector<float> d = batch_values(doubles, pairs, wl, count, &pdf_d), f = batch_values(floats, pairs, wl, count, &pdf_f);
    FloatAgainstDouble out;
    double num = 0.0, den = 0.0;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        num += (double(pdf_f[i]) - double(pdf_d[i])) * (double(pdf_f[i]) - double(pdf_d[i]));
        den += double(pdf_d[i]) * double(pdf_d[i]);
    }
    out.pdf_relative_rms = std::sqrt(num / den);
    npf::BrdfComparison comparison(count);
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        comparison.add(pairs[i].wi, pairs[i].wo, f.data() + i * count, d.data() + i * count);
        for (std::size_t k = 0; k < count; ++k) out.differing += f[i * count + k] != d[i * count + k];
    }
    out.comparison = comparison.result();
    return out;
}

double paired_psnr(const std::string& path) {
    npf::render::RenderOptions options;
    options.width = options.height = 48;
    options.threads = 1;
    const auto lights = npf::render::directional_lights();
    using npf::testing::BatchedBrdf;
    const npf::render::RenderResult d = npf::render::render_directional(BatchedBrdf(path, BatchPrecision::Double), lights, options);
    const npf::render::RenderResult f = npf::render::render_directional(BatchedBrdf(path, BatchPrecision::Float), lights, options);
    return npf::render::compare_images(d.image, f.image).psnr;
}

// The analytic cases: GGX with a detail layer whose residuals pull many values to the clamp at 0
// (where float's cancellation is largest), or without one.
std::string analytic_material(const std::string& path, const npf::testing::MicrofacetSpec& spec, bool detail,
                              const npf::DetailGrid& grid = {12, 8, 16}) {
    npf::NpfModel m = npf::compress_factors(npf::testing::make_microfacet_factors(spec), npf::CompressionOptions());
    if (detail) {
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> residual(-0.3f, 0.2f);
        std::vector<float> tables(m.channel_count() * grid.cells());
        for (float& v : tables) v = residual(rng);
        m.detail_grid = grid;
        m.detail = npf::compress_tables(tables, m.channel_count(), grid.cells(), 1.0, 0);
    }
    npf::write_npf_texture(m, path);
    return path;
}

// Anisotropic, 16 wavelengths, with a detail layer.
std::string analytic_anisotropic_spectral(const std::string& folder) {
    npf::testing::MicrofacetSpec spec;
    spec.alpha_x = 0.08, spec.alpha_y = 0.3;
    spec.spectral = true, spec.channels = 16;
    spec.d_phi = 32, spec.g_phi = 16;
    return analytic_material(folder + "/ggx_aniso_spectral_detail.exr", spec, true);
}

const std::string kShipped = std::string(NPF_SOURCE_DIR) + "/testsuite/farm-safety/unsealed/v2-rgb-detail.exr";

TEST(BatchFloat, ShippedRgbMaterialIsWithinTheBudget) {
    if (!npf::simd_isa_supported(npf::SimdIsa::Avx2)) GTEST_SKIP() << "no AVX2: the float setting is the double path";
    const FloatAgainstDouble r = compare_precisions(kShipped, BatchWavelengths::stored(), 3, reference_pairs());
    EXPECT_GT(r.differing, 0u) << "the float lanes did not run";
    EXPECT_LE(r.comparison.relative_rms, kBudgetRelativeRms);
    EXPECT_LE(r.pdf_relative_rms, kBudgetRelativeRms);
    std::printf("shipped RGB detail: relative RMS %.3g over %zu pairs (pdf %.3g), worst |difference| %.3g at %.4g\n",
                r.comparison.relative_rms, r.comparison.used, r.pdf_relative_rms,
                std::abs(r.comparison.worst.test - r.comparison.worst.reference), r.comparison.worst.reference);
    const double psnr = paired_psnr(kShipped);
    EXPECT_GE(psnr, kBudgetPsnr);
    std::printf("shipped RGB detail: paired directional render %.1f dB\n", psnr);
}

TEST(BatchFloat, AnalyticAnisotropicSpectralIsWithinTheBudget) {
    if (!npf::simd_isa_supported(npf::SimdIsa::Avx2)) GTEST_SKIP() << "no AVX2: the float setting is the double path";
    const std::string path = analytic_anisotropic_spectral(npf::testing::temporary_folder("npf-batch-float"));
    const std::vector<DirectionPair> pairs = reference_pairs();
    // Per-pair hero wavelengths, as a spectral renderer asks, and the stored channels.
    std::vector<float> hero;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> nm(400.f, 700.f);
    for (std::size_t i = 0; i < 4 * pairs.size(); ++i) hero.push_back(nm(rng));
    for (const bool stored : {false, true}) {
        SCOPED_TRACE(stored ? "stored channels" : "hero wavelengths");
        const BatchWavelengths wl = stored ? BatchWavelengths::stored() : BatchWavelengths::each_pair(hero.data(), 4);
        const FloatAgainstDouble r = compare_precisions(path, wl, stored ? 16 : 4, pairs);
        EXPECT_GT(r.differing, 0u) << "the float lanes did not run";
        EXPECT_LE(r.comparison.relative_rms, kBudgetRelativeRms);
        EXPECT_LE(r.pdf_relative_rms, kBudgetRelativeRms);
        std::printf("analytic %s: relative RMS %.3g over %zu pairs (pdf %.3g)\n", stored ? "stored" : "hero",
                    r.comparison.relative_rms, r.comparison.used, r.pdf_relative_rms);
    }
    const double psnr = paired_psnr(path);
    EXPECT_GE(psnr, kBudgetPsnr);
    std::printf("analytic: paired directional render %.1f dB\n", psnr);
}

// RGB with each table's azimuth and the detail layer on or off: the stored channels' own path
// (batch_stored_channels_float_avx2.cpp) in each of its forms, D and G with one column or many.
TEST(BatchFloat, StoredChannelsOfEveryTableShapeAreWithinTheBudget) {
    if (!npf::simd_isa_supported(npf::SimdIsa::Avx2)) GTEST_SKIP() << "no AVX2: the float setting is the double path";
    const std::string folder = npf::testing::temporary_folder("npf-batch-float-shapes");
    struct Shape {
        int d_phi, g_phi;
        bool detail;
    };
    for (const Shape& shape : {Shape{32, 16, true}, Shape{32, 1, false}, Shape{1, 16, true}, Shape{1, 1, false}}) {
        npf::testing::MicrofacetSpec spec;
        spec.alpha_x = 0.1, spec.alpha_y = 0.25;
        spec.d_phi = shape.d_phi, spec.g_phi = shape.g_phi;
        const std::string name = "rgb_" + std::to_string(shape.d_phi) + "_" + std::to_string(shape.g_phi) + (shape.detail ? "_detail" : "");
        SCOPED_TRACE(name);
        const std::string path = analytic_material(folder + "/" + name + ".exr", spec, shape.detail);
        const FloatAgainstDouble r = compare_precisions(path, BatchWavelengths::stored(), 3, reference_pairs());
        EXPECT_GT(r.differing, 0u) << "the float lanes did not run";
        EXPECT_LE(r.comparison.relative_rms, kBudgetRelativeRms);
        EXPECT_LE(r.pdf_relative_rms, kBudgetRelativeRms);
        std::printf("%s: relative RMS %.3g over %zu pairs (pdf %.3g)\n", name.c_str(), r.comparison.relative_rms,
                    r.comparison.used, r.pdf_relative_rms);
    }
}

// The smallest tables the format allows (one row, one column, a detail layer of one cell): every
// clamp, extrapolation and wrap lands on the padding of the copies.
TEST(BatchFloat, StoredChannelsOnTheSmallestTablesAreWithinTheBudget) {
    if (!npf::simd_isa_supported(npf::SimdIsa::Avx2)) GTEST_SKIP() << "no AVX2: the float setting is the double path";
    const std::string folder = npf::testing::temporary_folder("npf-batch-float-small");
    npf::testing::MicrofacetSpec spec;
    spec.set_grid(1, 1, 1, 1, 1);
    const std::string path = analytic_material(folder + "/one_cell.exr", spec, true, npf::DetailGrid{1, 1, 1});
    const FloatAgainstDouble r = compare_precisions(path, BatchWavelengths::stored(), 3, reference_pairs());
    EXPECT_GT(r.differing, 0u) << "the float lanes did not run";
    EXPECT_LE(r.comparison.relative_rms, kBudgetRelativeRms);
    EXPECT_LE(r.pdf_relative_rms, kBudgetRelativeRms);
    spec.set_grid(2, 3, 2, 2, 3);
    const std::string two = analytic_material(folder + "/two_rows.exr", spec, true, npf::DetailGrid{2, 1, 3});
    const FloatAgainstDouble r2 = compare_precisions(two, BatchWavelengths::stored(), 3, reference_pairs());
    EXPECT_LE(r2.comparison.relative_rms, kBudgetRelativeRms);
    EXPECT_LE(r2.pdf_relative_rms, kBudgetRelativeRms);
}

// sample_batch in float lanes: the same draws (double either way), its weights (eval_batch's
// values over its pdf) within the budget.
TEST(BatchFloat, SampleBatchDrawsAlikeAndWeighsWithinTheBudget) {
    if (!npf::simd_isa_supported(npf::SimdIsa::Avx2)) GTEST_SKIP() << "no AVX2: the float setting is the double path";
    NpfClosure doubles(kShipped), floats(kShipped);
    floats.set_batch_precision(BatchPrecision::Float);
    const std::size_t n = 1000;
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<float> vx, vy, vz, u1, u2;
    for (std::size_t i = 0; i < n; ++i) {
        const float z = 0.05f + 0.95f * u(rng), phi = 6.2831853f * u(rng), r = std::sqrt(1.f - z * z);
        vx.push_back(r * std::cos(phi)), vy.push_back(r * std::sin(phi)), vz.push_back(z);
        u1.push_back(u(rng)), u2.push_back(u(rng));
    }
    struct Out {
        std::vector<float> x, y, z, pdf, weights;
    };
    auto run = [&](const NpfClosure& c) {
        Out o{std::vector<float>(n), std::vector<float>(n), std::vector<float>(n), std::vector<float>(n), std::vector<float>(3 * n)};
        float* const light[3] = {o.x.data(), o.y.data(), o.z.data()};
        c.sample_batch(n, {vx.data(), vy.data(), vz.data()}, u1.data(), u2.data(), BatchWavelengths::stored(), light, o.pdf.data(),
                       o.weights.data());
        return o;
    };
    const Out d = run(doubles), f = run(floats);
    EXPECT_EQ(d.x, f.x);
    EXPECT_EQ(d.y, f.y);
    EXPECT_EQ(d.z, f.z);
    double num = 0.0, den = 0.0;
    for (std::size_t i = 0; i < 3 * n; ++i) {
        num += (double(f.weights[i]) - double(d.weights[i])) * (double(f.weights[i]) - double(d.weights[i]));
        den += double(d.weights[i]) * double(d.weights[i]);
    }
    EXPECT_GT(den, 0.0);
    EXPECT_LE(std::sqrt(num / den), kBudgetRelativeRms);
    std::printf("sample_batch weights: relative RMS %.3g\n", std::sqrt(num / den));
}

// The thresholds mean something: the same measures flag a path whose values are off by a few
// parts in 10^4 (half of float's 24 bits lost), which the float lanes must not be.
TEST(BatchFloat, TheBudgetCatchesAPerturbedPath) {
    const std::vector<DirectionPair> pairs = reference_pairs();
    NpfClosure c(kShipped);
    const std::vector<float> d = batch_values(c, pairs, BatchWavelengths::stored(), 3);
    npf::BrdfComparison comparison(3);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> noise(-3e-4f, 3e-4f);
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        float perturbed[3];
        for (int k = 0; k < 3; ++k) perturbed[k] = d[i * 3 + std::size_t(k)] * (1.f + noise(rng));
        comparison.add(pairs[i].wi, pairs[i].wo, perturbed, d.data() + i * 3);
    }
    EXPECT_GT(comparison.result().relative_rms, kBudgetRelativeRms);
}

}  // namespace
