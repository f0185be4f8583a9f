// The batched sample's draws for AVX2 (batch_draw.h). Compiled with -mavx2 and without FMA
// (CMakeLists.txt), called only where the CPU has AVX2 (npf_batch.cpp). Float steps run in float
// lanes and double steps in double lanes, each the scalar code's IEEE operation, so the draws
// equal NpfClosure::draw_light's to the bit (shading/tests/test_batch_closure.cpp).
#include "batch_draw.h"

#if defined(__AVX2__)
#include "simd_double4.h"

namespace npf::batch_detail {

namespace {

using simd::Double4;

// The largest float below 1: where the scalar code clamps a stretched number (std::min(x, k) is
// (k < x) ? k : x, which is _mm_min_ps(k, x) lane by lane, NaN included).
const __m128 kBelowOne = _mm_set1_ps(0x1.fffffep-1f);

__m128 clamp_below_one(__m128 x) { return _mm_min_ps(kBelowOne, x); }

Double4 to_double(__m128 x) { return Double4(_mm256_cvtps_pd(x)); }
__m128 to_float(Double4 x) { return _mm256_cvtpd_ps(x.v); }

}  // namespace

std::size_t draw_lights_avx2(const HalfVectorSampler& sampler, double diffuse_probability, std::size_t n,
                             const float* const view[3], const float* u1, const float* u2, float* const light[3],
                             std::uint8_t* redo) {
    const std::vector<AliasTable::Bin>& bins = sampler.cells().bins();
    const double* edges = sampler.half_sin2().data();
    const __m128 bin_count = _mm_set1_ps(float(bins.size()));
    const __m128i last_bin = _mm_set1_epi32(int(bins.size()) - 1);
    const Double4 columns(double(sampler.phi_cells()));
    const Double4 pd(diffuse_probability), spec_share(1.0 - diffuse_probability);
    const std::size_t groups = n - n % 4;
    for (std::size_t i = 0; i < groups; i += 4) {
        const __m128 wx = _mm_loadu_ps(view[0] + i), wy = _mm_loadu_ps(view[1] + i), wz = _mm_loadu_ps(view[2] + i);
        const __m128 second = _mm_loadu_ps(u2 + i);
        const Double4 second_d = to_double(second);
        // draw_light: a view above the horizon and u2 >= pd (compared in double) take the
        // half-vector strategy.
        const int take = _mm_movemask_ps(_mm_cmpgt_ps(wz, _mm_setzero_ps())) & ~_mm256_movemask_pd((second_d < pd).m) & 0xF;
        for (int k = 0; k < 4; ++k) redo[i + std::size_t(k)] = std::uint8_t(((take >> k) & 1) == 0);
        if (take == 0) continue;
        const __m128 v = clamp_below_one(to_float((second_d - pd) / spec_share));

        // AliasTable::sample(u1).
        const __m128 scaled = _mm_mul_ps(_mm_loadu_ps(u1 + i), bin_count);
        // std::min(std::size_t(scaled), size - 1): a negative or NaN conversion is a huge unsigned
        // number there as here (unsigned minimum), which gives the last bin.
        const __m128i bin = _mm_min_epu32(_mm_cvttps_epi32(scaled), last_bin);
        const __m128 f = clamp_below_one(_mm_sub_ps(scaled, _mm_cvtepi32_ps(bin)));
        alignas(16) std::int32_t b[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(b), bin);
        const __m128 keep = _mm_setr_ps(bins[std::size_t(b[0])].keep, bins[std::size_t(b[1])].keep,
                                        bins[std::size_t(b[2])].keep, bins[std::size_t(b[3])].keep);
        const __m128i alias = _mm_setr_epi32(int(bins[std::size_t(b[0])].alias), int(bins[std::size_t(b[1])].alias),
                                             int(bins[std::size_t(b[2])].alias), int(bins[std::size_t(b[3])].alias));
        const __m128 kept = _mm_cmplt_ps(f, keep);
        const __m128 remainder_kept = clamp_below_one(_mm_div_ps(f, keep));
        const __m128 remainder_alias = clamp_below_one(_mm_div_ps(_mm_sub_ps(f, keep), _mm_sub_ps(_mm_set1_ps(1.f), keep)));
        const __m128i cell = _mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(alias), _mm_castsi128_ps(bin), kept));
        const __m128 remainder = _mm_blendv_ps(remainder_alias, remainder_kept, kept);

        // HalfVectorSampler::sample: the cell's row and column, then its direction.
        const Double4 cell_d(_mm256_cvtepi32_pd(cell));
        const Double4 row = simd::floor(cell_d / columns), column = cell_d - row * columns;
        alignas(16) std::int32_t r[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(r), _mm256_cvtpd_epi32(row.v));
        const Double4 s0(_mm256_setr_pd(edges[r[0]], edges[r[1]], edges[r[2]], edges[r[3]]));
        const Double4 s1(_mm256_setr_pd(edges[r[0] + 1], edges[r[1] + 1], edges[r[2] + 1], edges[r[3] + 1]));
        Double4 x, y, z;
        HalfVectorSampler::direction_in_cell(s0, s1, to_double(remainder), column, to_double(v), columns, x, y, z);
        const __m128 hx = to_float(x), hy = to_float(y), hz = to_float(z);

        // reflect(view, h) in float, and a light at or below the horizon is no draw.
        const __m128 dot = _mm_add_ps(_mm_add_ps(_mm_mul_ps(wx, hx), _mm_mul_ps(wy, hy)), _mm_mul_ps(wz, hz));
        const __m128 d = _mm_mul_ps(_mm_set1_ps(2.f), dot);
        const __m128 lz = _mm_sub_ps(_mm_mul_ps(d, hz), wz);
        const __m128 above = _mm_cmpgt_ps(lz, _mm_setzero_ps());
        _mm_storeu_ps(light[0] + i, _mm_and_ps(above, _mm_sub_ps(_mm_mul_ps(d, hx), wx)));
        _mm_storeu_ps(light[1] + i, _mm_and_ps(above, _mm_sub_ps(_mm_mul_ps(d, hy), wy)));
        _mm_storeu_ps(light[2] + i, _mm_and_ps(above, lz));
    }
    return groups;
}

}  // namespace npf::batch_detail
#else
namespace npf::batch_detail {
std::size_t draw_lights_avx2(const HalfVectorSampler&, double, std::size_t, const float* const[3], const float*,
                             const float*, float* const[3], std::uint8_t*) {
    return 0;
}
}  // namespace npf::batch_detail
#endif
