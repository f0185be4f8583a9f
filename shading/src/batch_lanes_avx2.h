// What the batched closure's vector code needs of a lane type beyond its arithmetic
// (simd_double4.h, simd_float8.h): its scalar and index types, the loads of a block's fields, the
// lanes to keep (pairs in the domain), the store of finished values, and the loads of table cells
// lane by lane, transposed so that each vector holds one number of every lane. Included only by
// the files compiled for AVX2 (batch_values_avx2.cpp, batch_stored_channels_float_avx2.cpp).
#pragma once

#include "simd_double4.h"
#include "simd_float8.h"

#include <npf/core/channels.h>
#include <npf/shading/detail_grid.h>

#include <cstddef>
#include <cstdint>

namespace npf::batch_detail {
// Internal linkage in each file that includes this: the files are compiled for different
// instruction sets (with FMA for the float lanes, without for the double lanes' bits), and a
// weak, shared copy of one of these functions could be the one the linker keeps for all
// (tests/check_isa_objects.cmake).
namespace {
namespace lanes {

using simd::Double4;
using simd::Float8;

// Lanes<Double4> (four pairs in double) and Lanes<Float8> (eight in float).
template <class V>
struct Lanes;

template <>
struct Lanes<Double4> {
    using Scalar = double;
    using Index = __m128i;
    using Keep = __m256d;
    static constexpr int kCount = 4;
    static Double4 load(const double* p) { return simd::load4(p); }
    static Keep keep_of(const std::uint8_t* valid) { return simd::nonzero_bytes4(valid).m; }
    static bool none(Keep k) { return _mm256_testz_pd(k, k) != 0; }
    static Double4 keep(Keep k, Double4 a) { return Double4(_mm256_and_pd(k, a.v)); }
    static void store(float* out, Double4 v) { _mm_storeu_ps(out, _mm256_cvtpd_ps(v.v)); }
    static void store_zero(float* out) { _mm_storeu_ps(out, _mm_setzero_ps()); }
    static Index load_index(const std::int32_t* p) { return _mm_load_si128(reinterpret_cast<const __m128i*>(p)); }
    // c * a + b per lane.
    static Index mul_add(Index c, int a, int b) { return _mm_add_epi32(_mm_mullo_epi32(c, _mm_set1_epi32(a)), _mm_set1_epi32(b)); }
    static Index add(Index c, Index d) { return _mm_add_epi32(c, d); }
    // WavelengthLocator::locate of nm[lane * stride] for each lane: the channels around each
    // wavelength and the weight of the second.
    static void locate(const WavelengthLocator& locator, const float* nm, std::size_t stride, Index& c0, Index& c1, Double4& t) {
        alignas(16) std::int32_t i0[4], i1[4];
        alignas(32) double w[4];
        for (std::size_t lane = 0; lane < 4; ++lane) {
            std::uint32_t a, b;
            float tf;
            locator.locate(nm[lane * stride], a, b, tf);
            i0[lane] = std::int32_t(a), i1[lane] = std::int32_t(b), w[lane] = double(tf);
        }
        c0 = _mm_load_si128(reinterpret_cast<const __m128i*>(i0));
        c1 = _mm_load_si128(reinterpret_cast<const __m128i*>(i1));
        t = simd::load4(w);
    }
    // The eight floats from base + stride * index[lane] for each lane (a channel record, or two
    // paired cells), as columns: column k holds float k of the lanes' eight (as eight gathers would).
    static void columns8(const float* base, std::size_t stride, Index index, Double4 columns[8]) {
        alignas(16) std::int32_t i[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(i), index);
        __m128 lo[4], hi[4];
        for (int k = 0; k < 4; ++k) {
            const float* r = base + stride * std::size_t(i[k]);
            lo[k] = _mm_loadu_ps(r), hi[k] = _mm_loadu_ps(r + 4);
        }
        _MM_TRANSPOSE4_PS(lo[0], lo[1], lo[2], lo[3]);
        _MM_TRANSPOSE4_PS(hi[0], hi[1], hi[2], hi[3]);
        for (int k = 0; k < 4; ++k) columns[k] = Double4(_mm256_cvtps_pd(lo[k])), columns[4 + k] = Double4(_mm256_cvtps_pd(hi[k]));
    }
};

template <>
struct Lanes<Float8> {
    using Scalar = float;
    using Index = __m256i;
    using Keep = __m256;
    static constexpr int kCount = 8;
    static Float8 load(const float* p) { return simd::load8(p); }
    static Keep keep_of(const std::uint8_t* valid) { return simd::nonzero_bytes8(valid).m; }
    static bool none(Keep k) { return _mm256_testz_ps(k, k) != 0; }
    static Float8 keep(Keep k, Float8 a) { return Float8(_mm256_and_ps(k, a.v)); }
    static void store(float* out, Float8 v) { _mm256_storeu_ps(out, v.v); }
    static void store_zero(float* out) { _mm256_storeu_ps(out, _mm256_setzero_ps()); }
    static Index load_index(const std::int32_t* p) { return _mm256_load_si256(reinterpret_cast<const __m256i*>(p)); }
    static Index mul_add(Index c, int a, int b) {
        return _mm256_add_epi32(_mm256_mullo_epi32(c, _mm256_set1_epi32(a)), _mm256_set1_epi32(b));
    }
    static Index add(Index c, Index d) { return _mm256_add_epi32(c, d); }
    // locate() as vector code, each step WavelengthLocator::locate's on eight lanes (the same
    // results); lane by lane where a wavelength is outside the grid or the grid has no buckets.
    static void locate(const WavelengthLocator& locator, const float* nm, std::size_t stride, Index& c0, Index& c1, Float8& t) {
        const WavelengthLocator::Tables w = locator.tables();
        alignas(32) float lambda[8];
        for (std::size_t lane = 0; lane < 8; ++lane) lambda[lane] = nm[lane * stride];
        const __m256 x = _mm256_load_ps(lambda);
        const __m256 inside =
            _mm256_and_ps(_mm256_cmp_ps(x, _mm256_set1_ps(w.lo), _CMP_GE_OQ), _mm256_cmp_ps(x, _mm256_set1_ps(w.hi), _CMP_LE_OQ));
        if (!w.start || _mm256_movemask_ps(inside) != 0xFF) {
            alignas(32) std::int32_t i0[8], i1[8];
            alignas(32) float tf[8];
            for (std::size_t lane = 0; lane < 8; ++lane) {
                std::uint32_t a, b;
                locator.locate(lambda[lane], a, b, tf[lane]);
                i0[lane] = std::int32_t(a), i1[lane] = std::int32_t(b);
            }
            c0 = load_index(i0), c1 = load_index(i1), t = simd::load8(tf);
            return;
        }
        const __m256i one = _mm256_set1_epi32(1), last = _mm256_set1_epi32(int(w.n) - 1);
        const __m256 scaled = _mm256_mul_ps(_mm256_sub_ps(x, _mm256_set1_ps(w.lo)), _mm256_set1_ps(w.buckets_per_nm));
        const __m256i bucket = _mm256_min_epi32(_mm256_cvttps_epi32(scaled), _mm256_set1_epi32(int(w.buckets) - 1));
        __m256i i = gather_int(w.start, bucket);
        for (;;) {  // up while the next grid wavelength is at or below lambda
            const __m256i next = _mm256_add_epi32(i, one);
            const __m256i up = _mm256_and_si256(_mm256_cmpgt_epi32(_mm256_add_epi32(last, one), next),
                                                _mm256_castps_si256(_mm256_cmp_ps(
                                                    simd::gather(w.grid, _mm256_min_epi32(next, last)).v, x, _CMP_LE_OQ)));
            if (_mm256_testz_si256(up, up)) break;
            i = _mm256_sub_epi32(i, up);
        }
        for (;;) {  // down while this one is above lambda
            const __m256i down = _mm256_and_si256(_mm256_cmpgt_epi32(i, _mm256_setzero_si256()),
                                                  _mm256_castps_si256(_mm256_cmp_ps(simd::gather(w.grid, i).v, x, _CMP_GT_OQ)));
            if (_mm256_testz_si256(down, down)) break;
            i = _mm256_add_epi32(i, down);
        }
        // blend_wavelengths_at at min(i, n - 2).
        c0 = _mm256_min_epi32(i, _mm256_sub_epi32(last, one));
        c1 = _mm256_add_epi32(c0, one);
        const Float8 g0 = simd::gather(w.grid, c0), span = simd::gather(w.grid, c1) - g0;
        const Float8 v = (Float8(x) - g0) / span;
        const Float8 clamped = simd::select(v < Float8(0.0), Float8(0.0), simd::select(Float8(1.0) < v, Float8(1.0), v));
        t = simd::select(span > Float8(0.0), clamped, Float8(0.0));
    }
    static __m256i gather_int(const std::uint32_t* table, __m256i index) {
        alignas(32) std::int32_t i[8];
        _mm256_store_si256(reinterpret_cast<__m256i*>(i), index);
        return _mm256_setr_epi32(int(table[i[0]]), int(table[i[1]]), int(table[i[2]]), int(table[i[3]]), int(table[i[4]]),
                                 int(table[i[5]]), int(table[i[6]]), int(table[i[7]]));
    }
    static void columns8(const float* base, std::size_t stride, Index index, Float8 columns[8]) {
        alignas(32) std::uint32_t offset[8];
        byte_offsets(index, stride, offset);
        __m256 r[8];
        for (int k = 0; k < 8; ++k) r[k] = _mm256_loadu_ps(at_offset(base, offset[k]));
        transpose8(r, columns);
    }
    // index[lane] * stride floats (4 or 8) in bytes, unsigned: one shift for all lanes, where a
    // signed index per lane costs a sign extension and a shift before each load.
    static void byte_offsets(Index index, std::size_t stride, std::uint32_t out[8]) {
        _mm256_store_si256(reinterpret_cast<__m256i*>(out), stride == 8 ? _mm256_slli_epi32(index, 5) : _mm256_slli_epi32(index, 4));
    }
    static const float* at_offset(const float* base, std::uint32_t bytes) {
        return reinterpret_cast<const float*>(reinterpret_cast<const char*>(base) + bytes);
    }
    // For each lane, the sum over q of scale[q] times the eight floats at cell index + offset[q]
    // (two cells of four floats side by side), as columns (columns8's layout): each lane's sum in
    // its own register, its scales broadcast from memory, then one transpose, where columns8 per
    // q would transpose Q times (the shuffles bound the float lanes' lookups).
    template <int Q>
    static void weighted_columns8(const float* base, Index index, const std::size_t offset[Q], const Float8 scale[Q],
                                  Float8 columns[8]) {
        alignas(32) std::uint32_t i[8];
        alignas(32) float w[Q][8];
        byte_offsets(index, 4, i);
        for (int q = 0; q < Q; ++q) _mm256_store_ps(w[q], scale[q].v);
        __m256 r[8];
        for (int k = 0; k < 8; ++k) {
            const float* cell = at_offset(base, i[k]);
            __m256 sum = _mm256_mul_ps(_mm256_loadu_ps(cell + 4 * offset[0]), _mm256_broadcast_ss(&w[0][k]));
            for (int q = 1; q < Q; ++q) sum = _mm256_fmadd_ps(_mm256_loadu_ps(cell + 4 * offset[q]), _mm256_broadcast_ss(&w[q][k]), sum);
            r[k] = sum;
        }
        transpose8(r, columns);
    }
    // The four ranks of a detail layer's padded copy (padded_detail_cells_of; `offset` from
    // detail_corner_offsets) at the trilinear position (h, d, p): the corner pairs weighted along
    // theta_h and theta_d per lane (weighted_columns8), then blended along phi_d.
    NPF_GENERIC_INLINE static void padded_detail_ranks(const DetailGrid& grid, const float* padded, const std::size_t offset[4],
                                                       const table::LerpOf<Float8>& h, const table::LerpOf<Float8>& d,
                                                       const table::LerpOf<Float8>& p, Float8 out[4]) {
        const Float8 rows = Float8(double(grid.theta_d + 1)), cols = Float8(double(grid.phi_d + 1));
        Float8 scale[4];
        for (int q = 0; q < 4; ++q) scale[q] = (q & 2 ? h.t : Float8(1.0) - h.t) * (q & 1 ? d.t : Float8(1.0) - d.t);
        Float8 c[8];
        weighted_columns8<4>(padded, simd::to_int32((h.i0 * rows + d.i0) * cols + p.i0), offset, scale, c);
        for (int k = 0; k < 4; ++k) out[k] = c[k] + p.t * (c[4 + k] - c[k]);
    }
    static void transpose8(const __m256 r[8], Float8 columns[8]) {
        // The 8 x 8 transpose: pairs, then quadruples within each 128-bit half, then the halves.
        const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
        const __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
        const __m256 t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
        const __m256 t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
        const __m256 u0 = _mm256_shuffle_ps(t0, t2, 0x44), u1 = _mm256_shuffle_ps(t0, t2, 0xEE);
        const __m256 u2 = _mm256_shuffle_ps(t1, t3, 0x44), u3 = _mm256_shuffle_ps(t1, t3, 0xEE);
        const __m256 u4 = _mm256_shuffle_ps(t4, t6, 0x44), u5 = _mm256_shuffle_ps(t4, t6, 0xEE);
        const __m256 u6 = _mm256_shuffle_ps(t5, t7, 0x44), u7 = _mm256_shuffle_ps(t5, t7, 0xEE);
        columns[0] = Float8(_mm256_permute2f128_ps(u0, u4, 0x20));
        columns[1] = Float8(_mm256_permute2f128_ps(u1, u5, 0x20));
        columns[2] = Float8(_mm256_permute2f128_ps(u2, u6, 0x20));
        columns[3] = Float8(_mm256_permute2f128_ps(u3, u7, 0x20));
        columns[4] = Float8(_mm256_permute2f128_ps(u0, u4, 0x31));
        columns[5] = Float8(_mm256_permute2f128_ps(u1, u5, 0x31));
        columns[6] = Float8(_mm256_permute2f128_ps(u2, u6, 0x31));
        columns[7] = Float8(_mm256_permute2f128_ps(u3, u7, 0x31));
    }
};

// NpfClosure::write_values' last step: finite_float(max(0, v) cos_light), then 0 outside the domain.
template <class V>
void store_values(V v, V cos_light, typename Lanes<V>::Keep keep, float* out) {
    v = simd::select(V(0.0) < v, v, V(0.0)) * cos_light;
    Lanes<V>::store(out, Lanes<V>::keep(keep, simd::finite_float_of(v)));
}

}  // namespace lanes
}  // namespace
}  // namespace npf::batch_detail
