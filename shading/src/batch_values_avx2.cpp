// The batched eval's table lookups for AVX2 (batch_values.h): four pairs per step in double
// lanes, or eight in float lanes (BatchPrecision::Float), by the same templates over the lane type.
// Compiled with -mavx2 and without FMA (CMakeLists.txt), called only where the CPU has AVX2
// (npf_batch.cpp). Every sum below is NpfModel::position's and NpfModel::value's, term for term in
// their order, so that each double lane gets the scalar closure's bits
// (shading/tests/test_batch_closure.cpp); float lanes are held to the float budget
// (shading/tests/test_batch_float.cpp). Compiled twice: as itself, the double lanes (values_avx2), and
// through batch_values_float_avx2.cpp with NPF_BATCH_VALUES_FLOAT, the float lanes
// (values_float_avx2) with FMA and contracted multiply-adds, which only they may have.
#include "batch_values.h"

#if defined(__AVX2__)
#include "simd_double4.h"
#include "simd_float8.h"

#include <npf/shading/npf_equation.h>

#include <type_traits>

namespace npf::batch_detail {

namespace {

using simd::Double4;
using simd::Float8;
using table::LerpOf;

// What the templates below need of a lane type beyond its arithmetic: its scalar and index types,
// loads of a block's fields, the lanes to keep (pairs in the domain), the store of finished values,
// and a cell's four ranks per lane.
template <class V>
struct Lanes;

template <>
struct Lanes<Double4> {
    using Scalar = double;
    using Index = __m128i;
    using Keep = __m256d;
    static constexpr int kCount = 4;
    static Double4 load(const double* p) { return simd::load4(p); }
    static Keep keep_of(const std::uint8_t* valid) {
        return _mm256_castsi256_pd(_mm256_set_epi64x(-std::int64_t(valid[3] != 0), -std::int64_t(valid[2] != 0),
                                                     -std::int64_t(valid[1] != 0), -std::int64_t(valid[0] != 0)));
    }
    static bool none(Keep k) { return _mm256_testz_pd(k, k) != 0; }
    static Double4 keep(Keep k, Double4 a) { return Double4(_mm256_and_pd(k, a.v)); }
    static void store(float* out, Double4 v) { _mm_storeu_ps(out, _mm256_cvtpd_ps(v.v)); }
    static void store_zero(float* out) { _mm_storeu_ps(out, _mm_setzero_ps()); }
    static Index load_index(const std::int32_t* p) { return _mm_load_si128(reinterpret_cast<const __m128i*>(p)); }
    // c * a + b per lane.
    static Index mul_add(Index c, int a, int b) { return _mm_add_epi32(_mm_mullo_epi32(c, _mm_set1_epi32(a)), _mm_set1_epi32(b)); }
    static Index add(Index c, Index d) { return _mm_add_epi32(c, d); }
    // Ranks 0..3 of cell index[lane] of a cell-major table (cell_major_of) for each lane: one load
    // per lane, then a transpose, so that ranks[r] holds rank r of the lanes (as gather would).
    static void corner_ranks(const float* cells, Index index, Double4 ranks[4]) {
        alignas(16) std::int32_t i[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(i), index);
        __m128 a = _mm_loadu_ps(cells + 4 * std::size_t(i[0])), b = _mm_loadu_ps(cells + 4 * std::size_t(i[1]));
        __m128 c = _mm_loadu_ps(cells + 4 * std::size_t(i[2])), d = _mm_loadu_ps(cells + 4 * std::size_t(i[3]));
        _MM_TRANSPOSE4_PS(a, b, c, d);
        ranks[0] = Double4(_mm256_cvtps_pd(a));
        ranks[1] = Double4(_mm256_cvtps_pd(b));
        ranks[2] = Double4(_mm256_cvtps_pd(c));
        ranks[3] = Double4(_mm256_cvtps_pd(d));
    }
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
    static Keep keep_of(const std::uint8_t* valid) {  // the eight bytes widened, then != 0
        const __m256i lanes = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(valid)));
        return _mm256_castsi256_ps(_mm256_xor_si256(_mm256_cmpeq_epi32(lanes, _mm256_setzero_si256()), _mm256_set1_epi32(-1)));
    }
    static bool none(Keep k) { return _mm256_testz_ps(k, k) != 0; }
    static Float8 keep(Keep k, Float8 a) { return Float8(_mm256_and_ps(k, a.v)); }
    static void store(float* out, Float8 v) { _mm256_storeu_ps(out, v.v); }
    static void store_zero(float* out) { _mm256_storeu_ps(out, _mm256_setzero_ps()); }
    static Index load_index(const std::int32_t* p) { return _mm256_load_si256(reinterpret_cast<const __m256i*>(p)); }
    static Index mul_add(Index c, int a, int b) {
        return _mm256_add_epi32(_mm256_mullo_epi32(c, _mm256_set1_epi32(a)), _mm256_set1_epi32(b));
    }
    static Index add(Index c, Index d) { return _mm256_add_epi32(c, d); }
    static void corner_ranks(const float* cells, Index index, Float8 ranks[4]) {
        alignas(32) std::int32_t i[8];
        _mm256_store_si256(reinterpret_cast<__m256i*>(i), index);
        __m128 r[8];
        for (int k = 0; k < 8; ++k) r[k] = _mm_loadu_ps(cells + 4 * std::size_t(i[k]));
        _MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);
        _MM_TRANSPOSE4_PS(r[4], r[5], r[6], r[7]);
        for (int k = 0; k < 4; ++k) ranks[k] = Float8(_mm256_set_m128(r[4 + k], r[k]));
    }
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
        alignas(32) std::int32_t i[8];
        _mm256_store_si256(reinterpret_cast<__m256i*>(i), index);
        __m256 r[8];
        for (int k = 0; k < 8; ++k) r[k] = _mm256_loadu_ps(base + stride * std::size_t(i[k]));
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

// The interpolated basis values of one table at a group of pairs: gathers from each basis table.
template <class V>
struct Corners {
    typename Lanes<V>::Index index[4];
    // In the paired copy (paired_cells_of): corners 0 and 2 (their rows, side by side), or
    // corners 0 and 1 at pair[0] and corners 2 and 3 at pair[1].
    typename Lanes<V>::Index pair[2];
    V weight[4];
    bool one_column;  // corners 1 and 3 are corners 0 and 2 (a table of one column): gathered once
};

template <class V>
NPF_GENERIC_INLINE Corners<V> bilinear_of(const LerpOf<V>& row, const LerpOf<V>& col, int cols, bool paired) {
    const V c = V(double(cols));
    const V r0 = row.i0 * c, r1 = row.i1 * c;
    Corners<V> k;
    k.one_column = cols == 1;
    if (paired && k.one_column) {
        k.pair[0] = simd::to_int32(row.i0);
    } else if (paired) {
        const V padded = V(double(cols + 1));
        k.pair[0] = simd::to_int32(row.i0 * padded + col.i0);
        k.pair[1] = simd::to_int32(row.i1 * padded + col.i0);
    } else {
        k.index[0] = simd::to_int32(r0 + col.i0);
        k.index[1] = simd::to_int32(r0 + col.i1);
        k.index[2] = simd::to_int32(r1 + col.i0);
        k.index[3] = simd::to_int32(r1 + col.i1);
    }
    table::generic::bilinear_weights<V>(row.t, col.t, k.weight);
    return k;
}

// The bilinear value of each rank at a group of pairs: from the paired copy where there is one
// (the same products and sums, so the same bits), else gathered rank by rank. rank: s.rank, or
// the channel count for a paired copy of channel_tables_of's.
template <class V>
NPF_GENERIC_INLINE void project(const SpectralBasis& s, int rank, const float* paired, const Corners<V>& k, V* out) {
    if (paired) {
        V a[8];  // ranks of the first cell of the pair in a[0..3], of the second in a[4..7]
        Lanes<V>::columns8(paired, 4, k.pair[0], a);
        if (k.one_column) {
            for (int r = 0; r < rank; ++r) out[r] = a[r] * k.weight[0] + a[r] * k.weight[1] + a[4 + r] * k.weight[2] + a[4 + r] * k.weight[3];
            return;
        }
        V b[8];
        Lanes<V>::columns8(paired, 4, k.pair[1], b);
        for (int r = 0; r < rank; ++r) out[r] = a[r] * k.weight[0] + a[4 + r] * k.weight[1] + b[r] * k.weight[2] + b[4 + r] * k.weight[3];
        return;
    }
    const float* t = s.basis.data();
    if (k.one_column) {
        for (int r = 0; r < s.rank; ++r, t += s.cells) {
            const V v0 = simd::gather(t, k.index[0]), v2 = simd::gather(t, k.index[2]);
            out[r] = v0 * k.weight[0] + v0 * k.weight[1] + v2 * k.weight[2] + v2 * k.weight[3];
        }
        return;
    }
    for (int r = 0; r < s.rank; ++r, t += s.cells) {
        out[r] = simd::gather(t, k.index[0]) * k.weight[0] + simd::gather(t, k.index[1]) * k.weight[1] +
                 simd::gather(t, k.index[2]) * k.weight[2] + simd::gather(t, k.index[3]) * k.weight[3];
    }
}

// What every channel of a group of pairs shares (NpfModel::Lookup, as vectors).
template <class V>
struct Group {
    V cos_o, inv_cos_product, f_t;
    typename Lanes<V>::Index f0, f1;
    bool f_cells;                 // F of every channel at f0 and f1 below (cell-major F, stored channels)
    V f_at0[4], f_at1[4];
    V d[kVectorRank], g_i[kVectorRank], g_o[kVectorRank], r[kVectorRank];
};

template <class V>
LerpOf<V> g_column(V phi, int g_phi) {
    if (g_phi == 1) return {V(0.0), V(0.0), V(0.0)};
    return equation::column_of(phi, g_phi);
}

// NpfModel::position for the group of pairs from j of the block; lanes outside the domain (keep
// false) look up at angles 0 (valid cells; their values are zeroed later). per_channel: from the
// channel tables (cells.channel_*), g.d, g.g_i, g.g_o and g.r then holding each channel's value.
template <class V>
void position(const NpfModel& m, const CellMajorBases& cells, const BlockAnglesOf<typename Lanes<V>::Scalar>& a,
              std::size_t j, typename Lanes<V>::Keep keep, bool stored, bool per_channel, Group<V>& g) {
    using L = Lanes<V>;
    const int channels = int(m.channel_count());
    const float* d_cells = per_channel ? cells.channel_d : cells.d;
    const float* g_cells = per_channel ? cells.channel_g : cells.g;
    const float* detail_cells = per_channel ? cells.channel_detail : cells.detail;
    const int d_rank = per_channel ? channels : m.D.rank, g_rank = per_channel ? channels : m.G.rank;
    const int detail_rank = per_channel ? channels : m.detail.rank;
    auto at = [&](const typename L::Scalar* field) { return L::keep(keep, L::load(field + j)); };
    g.cos_o = at(a.cos_o);
    g.inv_cos_product = at(a.inv_cos_product);
    const V u_h = at(a.u_h), theta_d = at(a.theta_d);
    project(m.D, d_rank, d_cells, bilinear_of(equation::d_row_of(u_h, m.d_theta), equation::column_of(at(a.phi_h), m.d_phi), m.d_phi, d_cells), g.d);
    const LerpOf<V> f = equation::f_row_of(theta_d, m.f_theta);
    g.f0 = simd::to_int32(f.i0);
    g.f1 = simd::to_int32(f.i1);
    g.f_t = f.t;
    g.f_cells = stored && cells.f;
    if (g.f_cells) {
        L::corner_ranks(cells.f, g.f0, g.f_at0);
        L::corner_ranks(cells.f, g.f1, g.f_at1);
    }
    project(m.G, g_rank, g_cells, bilinear_of(equation::g_row_of(at(a.theta_gi), m.g_theta), g_column(at(a.phi_gi), m.g_phi), m.g_phi, g_cells), g.g_i);
    project(m.G, g_rank, g_cells, bilinear_of(equation::g_row_of(at(a.theta_go), m.g_theta), g_column(at(a.phi_go), m.g_phi), m.g_phi, g_cells), g.g_o);
    if (!m.has_detail()) return;
    const DetailGrid& grid = m.detail_grid;
    LerpOf<V> h, d, p;
    detail_position_of(grid, u_h, theta_d, at(a.phi_d), h, d, p);
    V weight[8];
    trilinear_weights<V>(h.t, d.t, p.t, weight);
    const V rows = V(double(grid.theta_d)), cols = V(double(grid.phi_d));
    if (detail_cells) {  // corners 2q and 2q + 1 (along phi_d) side by side; each rank's sum in the order below
        const V padded = V(double(grid.phi_d + 1));
        V sum[4] = {V(0.0), V(0.0), V(0.0), V(0.0)};  // all four ranks, in registers (the copy pads with 0)
        for (int q = 0; q < 4; ++q) {
            const V hi = q & 2 ? h.i1 : h.i0, di = q & 1 ? d.i1 : d.i0;
            V c[8];
            L::columns8(detail_cells, 4, simd::to_int32((hi * rows + di) * padded + p.i0), c);
            for (int r = 0; r < 4; ++r) sum[r] = sum[r] + c[r] * weight[2 * q];
            for (int r = 0; r < 4; ++r) sum[r] = sum[r] + c[4 + r] * weight[2 * q + 1];
        }
        for (int r = 0; r < detail_rank; ++r) g.r[r] = sum[r];
        return;
    }
    typename L::Index index[8];
    for (int k = 0; k < 8; ++k) {
        const V hi = k & 4 ? h.i1 : h.i0, di = k & 2 ? d.i1 : d.i0, pi = k & 1 ? p.i1 : p.i0;
        index[k] = simd::to_int32((hi * rows + di) * cols + pi);
    }
    const float* b = m.detail.basis.data();
    for (int r = 0; r < m.detail.rank; ++r, b += m.detail.cells) {
        V v(0.0);
        for (int k = 0; k < 8; ++k) v = v + simd::gather(b, index[k]) * weight[k];
        g.r[r] = v;
    }
}

// The channel of each lane: one for all (stored channels, shared wavelengths), or per lane. Each
// gives rho_d, rho_s, the weights of D's, G's and the detail layer's ranks, and F at a cell.
template <class V>
struct SameChannel {
    const NpfModel& m;
    std::size_t c;
    V of(const std::vector<float>& v) const { return V(double(v[c])); }
    V weight(const SpectralBasis& s, int k) const { return V(double(s.weights[c * std::size_t(s.rank) + std::size_t(k)])); }
    V rho_d() const { return of(m.rho_d); }
    V rho_s() const { return of(m.rho_s); }
    V d(int k) const { return weight(m.D, k); }
    V g(int k) const { return weight(m.G, k); }
    V detail(int k) const { return weight(m.detail, k); }
    V f(typename Lanes<V>::Index cell) const { return simd::gather(m.F.data() + c * std::size_t(m.f_theta), cell); }
    V f_value(const Group<V>& g) const {
        if (g.f_cells) return g.f_at0[c] * (V(1.0) - g.f_t) + g.f_at1[c] * g.f_t;
        return f(g.f0) * (V(1.0) - g.f_t) + f(g.f1) * g.f_t;
    }
};
// Per lane: from the channel records where the model has them (one load per lane and a
// transpose for every coefficient), else gathered one coefficient at a time.
template <class V>
struct LaneChannels {
    using L = Lanes<V>;
    const NpfModel& m;
    typename L::Index c;
    V column[8];
    bool records;
    LaneChannels(const NpfModel& model, const float* channel_records, typename L::Index channel)
        : m(model), c(channel), records(channel_records != nullptr) {
        if (records) L::columns8(channel_records, 8, c, column);
    }
    V gathered(const SpectralBasis& s, int k) const { return simd::gather(s.weights.data(), L::mul_add(c, s.rank, k)); }
    V rho_d() const { return records ? column[0] : simd::gather(m.rho_d.data(), c); }
    V rho_s() const { return records ? column[1] : simd::gather(m.rho_s.data(), c); }
    V d(int k) const { return records ? column[2 + k] : gathered(m.D, k); }
    V g(int k) const { return records ? column[2 + m.D.rank + k] : gathered(m.G, k); }
    V detail(int k) const { return records ? column[2 + m.D.rank + m.G.rank + k] : gathered(m.detail, k); }
    V f(typename L::Index cell) const { return simd::gather(m.F.data(), L::add(L::mul_add(c, m.f_theta, 0), cell)); }
    V f_value(const Group<V>& g) const { return f(g.f0) * (V(1.0) - g.f_t) + f(g.f1) * g.f_t; }
};

// NpfModel::value, term for term.
template <class V, class Channel>
NPF_GENERIC_INLINE V value_of(const NpfModel& m, const Group<V>& g, const Channel& c) {
    V d(0.0), gi(0.0), go(0.0);
    for (int k = 0; k < m.D.rank; ++k) d = d + c.d(k) * g.d[k];
    for (int k = 0; k < m.G.rank; ++k) {
        const V w = c.g(k);
        gi = gi + w * g.g_i[k];
        go = go + w * g.g_o[k];
    }
    const V fv = c.f_value(g);
    const V base = equation::value_of<V>(c.rho_d(), c.rho_s(), d, fv, gi, go, g.inv_cos_product);
    if (m.detail.rank == 0) return base;
    V r(0.0);
    for (int k = 0; k < m.detail.rank; ++k) r = r + c.detail(k) * g.r[k];
    return equation::with_detail_of<V>(base, r);
}

// The same from position's per_channel values (channel tables): no sums over ranks.
template <class V>
NPF_GENERIC_INLINE V channel_value_of(const NpfModel& m, const Group<V>& g, const SameChannel<V>& c) {
    const std::size_t k = c.c;
    const V base = equation::value_of<V>(c.rho_d(), c.rho_s(), g.d[k], c.f_value(g), g.g_i[k], g.g_o[k], g.inv_cos_product);
    if (m.detail.rank == 0) return base;
    return equation::with_detail_of<V>(base, g.r[k]);
}

// NpfClosure::write_values' last step: finite_float(max(0, v) cos_light), then 0 outside the domain.
template <class V>
void store_values(V v, V cos_light, typename Lanes<V>::Keep keep, float* out) {
    v = simd::select(V(0.0) < v, v, V(0.0)) * cos_light;
    Lanes<V>::store(out, Lanes<V>::keep(keep, simd::finite_float_of(v)));
}

template <class V>
std::size_t values_of(const NpfModel& m, const CellMajorBases& cells, const BlockAnglesOf<typename Lanes<V>::Scalar>& angles,
                      std::size_t count, const std::uint8_t* valid, const ValueRequestOfBlock& request, std::size_t first,
                      float* values, std::size_t n) {
    using L = Lanes<V>;
    constexpr std::size_t kLanes = std::size_t(L::kCount);
    Group<V> g;
    // Float lanes with stored channels look each channel up in its own tables where they exist
    // (channel_tables_of); the double path keeps the scalar closure's sums, to the bit.
    const bool per_channel = std::is_same<V, simd::Float8>::value && request.stored && cells.channel_d && cells.channel_g &&
                             (m.detail.rank == 0 || cells.channel_detail);
    std::size_t j = 0;
    for (; j + kLanes <= count; j += kLanes) {
        const typename L::Keep keep = L::keep_of(valid + j);
        float* out = values + first + j;
        if (L::none(keep)) {  // no lane shades
            for (std::size_t k = 0; k < request.count; ++k) L::store_zero(out + k * n);
            continue;
        }
        position<V>(m, cells, angles, j, keep, request.stored, per_channel, g);
        if (per_channel) {
            for (std::size_t k = 0; k < request.count; ++k)
                store_values(channel_value_of(m, g, SameChannel<V>{m, k}), g.cos_o, keep, out + k * n);
            continue;
        }
        if (request.stored) {
            for (std::size_t k = 0; k < request.count; ++k) store_values(value_of(m, g, SameChannel<V>{m, k}), g.cos_o, keep, out + k * n);
            continue;
        }
        const BatchWavelengths& wl = request.wavelengths;
        const float* nm = wl.nm + (wl.per_pair ? (first + j) * request.count : 0);
        const std::size_t stride = wl.per_pair ? request.count : 0;
        for (std::size_t k = 0; k < request.count; ++k) {
            typename L::Index c0, c1;
            V tv;
            L::locate(*request.locator, nm + k, stride, c0, c1, tv);
            const V a = value_of(m, g, LaneChannels<V>(m, cells.channel_records, c0));
            const V b = value_of(m, g, LaneChannels<V>(m, cells.channel_records, c1));
            // (1 - t) a + t b, and a itself where t is 0 (as write_values, which skips b there).
            const V v = simd::select(tv == V(0.0), a, (V(1.0) - tv) * a + tv * b);
            store_values(v, g.cos_o, keep, out + k * n);
        }
    }
    return j;
}

}  // namespace

#if !defined(NPF_BATCH_VALUES_FLOAT)
std::size_t values_avx2(const NpfModel& m, const CellMajorBases& cells, const BlockAngles& angles, std::size_t count,
                        const std::uint8_t* valid, const ValueRequestOfBlock& request, std::size_t first, float* values,
                        std::size_t n) {
    return values_of<Double4>(m, cells, angles, count, valid, request, first, values, n);
}
#else
std::size_t values_float_avx2(const NpfModel& m, const CellMajorBases& cells, const BlockAnglesOf<float>& angles,
                              std::size_t count, const std::uint8_t* valid, const ValueRequestOfBlock& request,
                              std::size_t first, float* values, std::size_t n) {
    return values_of<Float8>(m, cells, angles, count, valid, request, first, values, n);
}
#endif

}  // namespace npf::batch_detail

#else

namespace npf::batch_detail {

#if !defined(NPF_BATCH_VALUES_FLOAT)
std::size_t values_avx2(const NpfModel&, const CellMajorBases&, const BlockAngles&, std::size_t, const std::uint8_t*,
                        const ValueRequestOfBlock&, std::size_t, float*, std::size_t) {
    return 0;  // no vector path in this build: the caller shades every pair
}
#else
std::size_t values_float_avx2(const NpfModel&, const CellMajorBases&, const BlockAnglesOf<float>&, std::size_t,
                              const std::uint8_t*, const ValueRequestOfBlock&, std::size_t, float*, std::size_t) {
    return 0;
}
#endif

}  // namespace npf::batch_detail

#endif
