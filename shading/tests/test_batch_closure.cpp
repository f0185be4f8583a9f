// The batched closure (npf/shading/npf_batch.h): eval_batch, pdf_batch and sample_batch give,
// pair for pair, the scalar closure's values, pdfs, directions and weights to the bit, on the memory path with every instruction set
// this CPU has and on the texture path; stored channels, shared and per-pair wavelengths; pairs
// below the horizon, not finite, grazing, and batch sizes that are not a multiple of the block.
#include "npf_test_factors.h"
#include "synthetic_rgl.h"

#include <npf/fit/spectral_compression.h>
#include <npf/shading/npf_batch.h>
#include <npf/shading/npf_closure.h>
#include <npf/core/error.h>
#include <npf/core/simd_isa.h>
#include <npf/shading/npf_texture_file.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using npf::SimdIsa;
using npf::BatchWavelengths;
using npf::DirectionArrays;
using npf::NpfClosure;
using npf::Vec3;
using npf::WavelengthRequest;

struct Pairs {
    std::vector<float> vx, vy, vz, lx, ly, lz;
    std::size_t size() const { return vx.size(); }
    DirectionArrays view() const { return {vx.data(), vy.data(), vz.data()}; }
    DirectionArrays light() const { return {lx.data(), ly.data(), lz.data()}; }
    Vec3 view_at(std::size_t i) const { return {vx[i], vy[i], vz[i]}; }
    Vec3 light_at(std::size_t i) const { return {lx[i], ly[i], lz[i]}; }
};

// Random pairs over the hemisphere, every 17th below the horizon, every 29th with a NaN or an
// infinity, every 31st grazing (z = 1e-4), half near the mirror direction.
Pairs make_pairs(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    auto direction = [&](double z_min) {
        const double z = z_min + (1.0 - z_min) * uni(rng), phi = 2.0 * npf::kPiD * uni(rng), r = std::sqrt(1.0 - z * z);
        return Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
    };
    Pairs p;
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 v = direction(0.0), l = direction(0.0);
        if (i % 2) l = npf::normalize(Vec3(-v.x, -v.y, v.z) + direction(0.0) * 0.1f);
        if (i % 17 == 0) l.z = -l.z;
        if (i % 29 == 0) v.x = i % 58 == 0 ? std::numeric_limits<float>::quiet_NaN() : std::numeric_limits<float>::infinity();
        if (i % 31 == 0) v = npf::normalize(Vec3(v.x, v.y, 1e-4f));
        p.vx.push_back(v.x), p.vy.push_back(v.y), p.vz.push_back(v.z);
        p.lx.push_back(l.x), p.ly.push_back(l.y), p.lz.push_back(l.z);
    }
    return p;
}

std::vector<SimdIsa> isas() {
    std::vector<SimdIsa> out = {SimdIsa::Portable};
    if (npf::simd_isa_supported(SimdIsa::Avx2)) out.push_back(SimdIsa::Avx2);
    return out;
}

void expect_batch_equals_scalar(const NpfClosure& c, const Pairs& p, BatchWavelengths wl, const std::vector<float>& hero) {
    const std::size_t n = p.size();
    const std::size_t count = c.channels().is_rgb() || !wl.nm ? c.channel_count() : std::size_t(wl.count);
    std::vector<float> values(count * n, -1.f), pdf(n, -1.f), pdf_only(n, -1.f), scalar(count);
    c.eval_batch(n, p.view(), p.light(), wl, values.data(), pdf.data());
    c.pdf_batch(n, p.view(), p.light(), pdf_only.data());
    std::size_t nonzero = 0;
    for (std::size_t i = 0; i < n; ++i) {
        WavelengthRequest r = WavelengthRequest::stored();
        if (wl.nm) r = WavelengthRequest::at(wl.per_pair ? hero.data() + i * count : hero.data(), int(count));
        const float expected_pdf = c.eval(p.view_at(i), p.light_at(i), r, scalar.data());
        ASSERT_EQ(pdf[i], expected_pdf) << "pair " << i;
        ASSERT_EQ(pdf_only[i], c.pdf(p.view_at(i), p.light_at(i))) << "pair " << i;
        for (std::size_t k = 0; k < count; ++k) ASSERT_EQ(values[k * n + i], scalar[k]) << "pair " << i << ", value " << k;
        nonzero += scalar[0] > 0.f;
    }
    EXPECT_GT(nonzero, n / 2) << "the pairs should mostly shade";
}

void expect_sample_batch_equals_scalar(const NpfClosure& c, const Pairs& p, BatchWavelengths wl, const std::vector<float>& hero) {
    const std::size_t n = p.size();
    const std::size_t count = c.channels().is_rgb() || !wl.nm ? c.channel_count() : std::size_t(wl.count);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    std::vector<float> u1(n), u2(n);
    for (std::size_t i = 0; i < n; ++i) u1[i] = uni(rng), u2[i] = uni(rng);
    // The ends of [0, 1) and the strategies' boundary (u2 at the diffuse probability, in float,
    // and just beside it), where the vector draw's selects and clamps must follow the scalar's.
    const float below_one = 0x1.fffffep-1f, pd = float(c.diffuse_probability());
    for (std::size_t i = 0; i < n; ++i) {
        if (i % 7 == 3) u1[i] = i % 14 == 3 ? 0.f : below_one;
        if (i % 11 == 5) u2[i] = i % 22 == 5 ? 0.f : below_one;
        if (i % 13 == 6) u2[i] = i % 39 == 6 ? pd : std::nextafter(pd, i % 39 == 19 ? 0.f : 1.f);
    }
    std::vector<float> lx(n, -9.f), ly(n, -9.f), lz(n, -9.f), pdf(n, -1.f), weights(count * n, -1.f), pdf_only(n, -1.f);
    std::vector<float> lx2(n), ly2(n), lz2(n), scalar(count);
    float* const light[3] = {lx.data(), ly.data(), lz.data()};
    float* const light2[3] = {lx2.data(), ly2.data(), lz2.data()};
    c.sample_batch(n, p.view(), u1.data(), u2.data(), wl, light, pdf.data(), weights.data());
    c.sample_batch(n, p.view(), u1.data(), u2.data(), wl, light2, pdf_only.data(), nullptr);
    std::size_t drawn = 0;
    for (std::size_t i = 0; i < n; ++i) {
        WavelengthRequest r = WavelengthRequest::stored();
        if (wl.nm) r = WavelengthRequest::at(wl.per_pair ? hero.data() + i * count : hero.data(), int(count));
        npf::ClosureSample s;
        const bool ok = c.sample(p.view_at(i), u1[i], u2[i], r, s, scalar.data());
        ASSERT_EQ(pdf[i] > 0.f, ok) << "pair " << i;
        ASSERT_EQ(pdf_only[i], pdf[i]) << "pair " << i;
        ASSERT_EQ(lx2[i], lx[i]) << "pair " << i;
        if (!ok) {
            EXPECT_EQ(lx[i], 0.f);
            EXPECT_EQ(lz[i], 0.f);
            for (std::size_t k = 0; k < count; ++k) ASSERT_EQ(weights[k * n + i], 0.f) << "pair " << i;
            continue;
        }
        ++drawn;
        ASSERT_EQ(lx[i], s.light.x) << "pair " << i;
        ASSERT_EQ(ly[i], s.light.y) << "pair " << i;
        ASSERT_EQ(lz[i], s.light.z) << "pair " << i;
        ASSERT_EQ(pdf[i], s.pdf) << "pair " << i;
        for (std::size_t k = 0; k < count; ++k) ASSERT_EQ(weights[k * n + i], scalar[k]) << "pair " << i << ", weight " << k;
    }
    EXPECT_GT(drawn, n / 3);  // not vacuous (a D of one cell draws half vectors over the whole hemisphere: 42 % land)
}

// A detail layer of random residuals over `grid` (rank min(channels, cells)), large enough that
// model + residual falls below 0 in places: the vector path's trilinear lookup and its clamp.
npf::NpfModel with_random_detail(npf::NpfModel m, const npf::DetailGrid& grid, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> residual(-0.4f, 0.3f);
    const std::size_t C = m.channel_count(), cells = grid.cells();
    std::vector<float> tables(C * cells);
    for (float& v : tables) v = residual(rng);
    m.detail_grid = grid;
    m.detail = npf::compress_tables(tables, C, cells, 1.0, 0);
    return m;
}

TEST(BatchClosure, EqualsTheScalarClosureOnEveryPathAndInstructionSet) {
    const std::string folder = npf::testing::temporary_folder("npf-batch");
    struct Case {
        const char* name;
        npf::NpfModel model;
    };
    const npf::CompressionOptions full;
    npf::CompressionOptions rank_two;
    rank_two.d_rank = rank_two.g_rank = 2;
    npf::testing::MicrofacetSpec one_cell;  // every table one row and one column: the copies' padding
    one_cell.set_grid(1, 1, 1, 1, 1);
    const Case cases[] = {
        {"rgb_isotropic", npf::compress_factors(npf::testing::make_test_factors({false, 3, false, 4}), full)},
        {"spectral_anisotropic", npf::compress_factors(npf::testing::make_test_factors({true, 20, true, 5}), full)},
        {"rgb_isotropic_detail",
         with_random_detail(npf::compress_factors(npf::testing::make_test_factors({false, 3, false, 6}), full), {6, 5, 7}, 1)},
        {"spectral_anisotropic_detail_rank_two",
         with_random_detail(npf::compress_factors(npf::testing::make_test_factors({true, 12, true, 7}), rank_two), {5, 4, 9}, 2)},
        {"rgb_one_cell_tables_detail",
         with_random_detail(npf::compress_factors(npf::testing::make_microfacet_factors(one_cell), full), {1, 1, 1}, 3)},
    };
    const Pairs pairs = make_pairs(1000, 3);  // not a multiple of the block
    for (const Case& k : cases) {
        SCOPED_TRACE(k.name);
        const std::string path = folder + "/" + k.name + ".exr";
        npf::write_npf_texture(k.model, path);
        const NpfClosure memory(path, NpfClosure::Path::Memory), texture(path, NpfClosure::Path::Texture);
        std::vector<float> shared = {450.f, 517.5f, 600.f, 700.f}, per_pair;
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> nm(380.f, 720.f);
        for (std::size_t i = 0; i < 4 * pairs.size(); ++i) per_pair.push_back(nm(rng));
        for (SimdIsa isa : isas()) {
            SCOPED_TRACE(npf::simd_isa_name(isa));
            const npf::SimdIsaScope scope(isa);
            expect_batch_equals_scalar(memory, pairs, BatchWavelengths::stored(), {});
            expect_batch_equals_scalar(memory, pairs, BatchWavelengths::shared(shared.data(), 4), shared);
            expect_batch_equals_scalar(memory, pairs, BatchWavelengths::each_pair(per_pair.data(), 4), per_pair);
            expect_sample_batch_equals_scalar(memory, pairs, BatchWavelengths::each_pair(per_pair.data(), 4), per_pair);
            expect_sample_batch_equals_scalar(memory, pairs, BatchWavelengths::stored(), {});
        }
        expect_sample_batch_equals_scalar(texture, pairs, BatchWavelengths::shared(shared.data(), 4), shared);
        expect_batch_equals_scalar(texture, pairs, BatchWavelengths::each_pair(per_pair.data(), 4), per_pair);
    }
}

TEST(BatchClosure, EmptyAndSingleBatches) {
    const NpfClosure c(npf::compress_factors(npf::testing::make_test_factors({false, 3, false, 2}), npf::CompressionOptions()));
    c.eval_batch(0, {}, {}, BatchWavelengths::stored(), nullptr, nullptr);  // touches nothing
    c.pdf_batch(0, {}, {}, nullptr);
    Pairs one = make_pairs(2, 8);  // pair 0 is below the horizon by construction: keep pair 1
    for (auto* v : {&one.vx, &one.vy, &one.vz, &one.lx, &one.ly, &one.lz}) v->erase(v->begin());
    expect_batch_equals_scalar(c, one, BatchWavelengths::stored(), {});
}

TEST(BatchClosure, InstructionSetChoice) {
    EXPECT_TRUE(npf::simd_isa_supported(SimdIsa::Portable));
    EXPECT_NE(npf::simd_isa(), SimdIsa::Auto);  // Auto resolves to what runs
    if (!npf::simd_isa_supported(SimdIsa::Avx2)) {
        EXPECT_THROW(npf::set_simd_isa(SimdIsa::Avx2), npf::Error);
    }
    {
        const npf::SimdIsaScope scope(SimdIsa::Portable);
        EXPECT_EQ(npf::simd_isa(), SimdIsa::Portable);
    }
    EXPECT_STREQ(npf::simd_isa_name(SimdIsa::Avx2), "avx2");
}

}  // namespace
