// The batched eval's table lookups for AVX2 (batch_values.h): four pairs per step in double
// lanes, or eight in float lanes (BatchPrecision::Float), by the same templates over the lane type.
// Compiled with -mavx2 and without FMA (CMakeLists.txt), called only where the CPU has AVX2
// (npf_batch.cpp). Every sum below is NpfModel::position's and NpfModel::value's, term for term in
// their order, so that each double lane gets the scalar closure's bits
// (tests/test_batch_closure.cpp); float lanes are held to the float budget
// (tests/test_batch_float.cpp).
#include "batch_values.h"

#if defined(__AVX2__)
#include "simd_double4.h"
#include "simd_float8.h"

#include <npf/shading/npf_equation.h>

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
};

// The interpolated basis values of one table at a group of pairs: gathers from each basis table.
template <class V>
struct Corners {
    typename Lanes<V>::Index index[4];
    V weight[4];
    bool one_column;  // corners 1 and 3 are corners 0 and 2 (a table of one column): gathered once
};

template <class V>
Corners<V> bilinear_of(const LerpOf<V>& row, const LerpOf<V>& col, int cols) {
    const V c = V(double(cols));
    const V r0 = row.i0 * c, r1 = row.i1 * c;
    Corners<V> k;
    k.index[0] = simd::to_int32(r0 + col.i0);
    k.index[1] = simd::to_int32(r0 + col.i1);
    k.index[2] = simd::to_int32(r1 + col.i0);
    k.index[3] = simd::to_int32(r1 + col.i1);
    table::generic::bilinear_weights<V>(row.t, col.t, k.weight);
    k.one_column = cols == 1;
    return k;
}

// The bilinear value of each rank at a group of pairs: from the cell-major copy where there is one
// (the same products and sums, so the same bits), else gathered rank by rank.
template <class V>
void project(const SpectralBasis& s, const float* cell_major, const Corners<V>& k, V* out) {
    if (cell_major) {
        V c0[4], c1[4], c2[4], c3[4];
        Lanes<V>::corner_ranks(cell_major, k.index[0], c0);
        Lanes<V>::corner_ranks(cell_major, k.index[2], c2);
        if (k.one_column) {
            for (int r = 0; r < s.rank; ++r) out[r] = c0[r] * k.weight[0] + c0[r] * k.weight[1] + c2[r] * k.weight[2] + c2[r] * k.weight[3];
            return;
        }
        Lanes<V>::corner_ranks(cell_major, k.index[1], c1);
        Lanes<V>::corner_ranks(cell_major, k.index[3], c3);
        for (int r = 0; r < s.rank; ++r) out[r] = c0[r] * k.weight[0] + c1[r] * k.weight[1] + c2[r] * k.weight[2] + c3[r] * k.weight[3];
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
    V d[kVectorRank], g_i[kVectorRank], g_o[kVectorRank], r[kVectorRank];
};

template <class V>
LerpOf<V> g_column(V phi, int g_phi) {
    if (g_phi == 1) return {V(0.0), V(0.0), V(0.0)};
    return equation::column_of(phi, g_phi);
}

// NpfModel::position for the group of pairs from j of the block; lanes outside the domain (keep
// false) look up at angles 0 (valid cells; their values are zeroed later).
template <class V>
void position(const NpfModel& m, const CellMajorBases& cells, const BlockAnglesOf<typename Lanes<V>::Scalar>& a,
              std::size_t j, typename Lanes<V>::Keep keep, Group<V>& g) {
    using L = Lanes<V>;
    auto at = [&](const typename L::Scalar* field) { return L::keep(keep, L::load(field + j)); };
    g.cos_o = at(a.cos_o);
    g.inv_cos_product = at(a.inv_cos_product);
    const V u_h = at(a.u_h), theta_d = at(a.theta_d);
    project(m.D, cells.d, bilinear_of(equation::d_row_of(u_h, m.d_theta), equation::column_of(at(a.phi_h), m.d_phi), m.d_phi), g.d);
    const LerpOf<V> f = equation::f_row_of(theta_d, m.f_theta);
    g.f0 = simd::to_int32(f.i0);
    g.f1 = simd::to_int32(f.i1);
    g.f_t = f.t;
    project(m.G, cells.g, bilinear_of(equation::g_row_of(at(a.theta_gi), m.g_theta), g_column(at(a.phi_gi), m.g_phi), m.g_phi), g.g_i);
    project(m.G, cells.g, bilinear_of(equation::g_row_of(at(a.theta_go), m.g_theta), g_column(at(a.phi_go), m.g_phi), m.g_phi), g.g_o);
    if (!m.has_detail()) return;
    const DetailGrid& grid = m.detail_grid;
    LerpOf<V> h, d, p;
    detail_position_of(grid, u_h, theta_d, at(a.phi_d), h, d, p);
    V weight[8];
    trilinear_weights<V>(h.t, d.t, p.t, weight);
    typename L::Index index[8];
    const V rows = V(double(grid.theta_d)), cols = V(double(grid.phi_d));
    for (int k = 0; k < 8; ++k) {
        const V hi = k & 4 ? h.i1 : h.i0, di = k & 2 ? d.i1 : d.i0, pi = k & 1 ? p.i1 : p.i0;
        index[k] = simd::to_int32((hi * rows + di) * cols + pi);
    }
    if (cells.detail) {  // corner by corner, each rank's sum in the same order as below
        for (int r = 0; r < m.detail.rank; ++r) g.r[r] = V(0.0);
        for (int k = 0; k < 8; ++k) {
            V c[4];
            L::corner_ranks(cells.detail, index[k], c);
            for (int r = 0; r < m.detail.rank; ++r) g.r[r] = g.r[r] + c[r] * weight[k];
        }
        return;
    }
    const float* b = m.detail.basis.data();
    for (int r = 0; r < m.detail.rank; ++r, b += m.detail.cells) {
        V v(0.0);
        for (int k = 0; k < 8; ++k) v = v + simd::gather(b, index[k]) * weight[k];
        g.r[r] = v;
    }
}

// The channel of each lane: one for all (stored channels, shared wavelengths), or per lane.
template <class V>
struct SameChannel {
    std::size_t c;
    V weight(const std::vector<float>& w, int rank, int k) const { return V(double(w[c * std::size_t(rank) + std::size_t(k)])); }
    V of(const std::vector<float>& v) const { return V(double(v[c])); }
    V f(const NpfModel& m, typename Lanes<V>::Index cell) const { return simd::gather(m.F.data() + c * std::size_t(m.f_theta), cell); }
};
template <class V>
struct LaneChannels {
    using L = Lanes<V>;
    typename L::Index c;
    V weight(const std::vector<float>& w, int rank, int k) const { return simd::gather(w.data(), L::mul_add(c, rank, k)); }
    V of(const std::vector<float>& v) const { return simd::gather(v.data(), c); }
    V f(const NpfModel& m, typename L::Index cell) const { return simd::gather(m.F.data(), L::add(L::mul_add(c, m.f_theta, 0), cell)); }
};

// NpfModel::value, term for term.
template <class V, class Channel>
V value_of(const NpfModel& m, const Group<V>& g, const Channel& c) {
    V d(0.0), gi(0.0), go(0.0);
    for (int k = 0; k < m.D.rank; ++k) d = d + c.weight(m.D.weights, m.D.rank, k) * g.d[k];
    for (int k = 0; k < m.G.rank; ++k) {
        const V w = c.weight(m.G.weights, m.G.rank, k);
        gi = gi + w * g.g_i[k];
        go = go + w * g.g_o[k];
    }
    const V fv = c.f(m, g.f0) * (V(1.0) - g.f_t) + c.f(m, g.f1) * g.f_t;
    const V base = equation::value_of<V>(c.of(m.rho_d), c.of(m.rho_s), d, fv, gi, go, g.inv_cos_product);
    if (m.detail.rank == 0) return base;
    V r(0.0);
    for (int k = 0; k < m.detail.rank; ++k) r = r + c.weight(m.detail.weights, m.detail.rank, k) * g.r[k];
    return equation::with_detail_of<V>(base, r);
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
    std::size_t j = 0;
    for (; j + kLanes <= count; j += kLanes) {
        const typename L::Keep keep = L::keep_of(valid + j);
        float* out = values + first + j;
        if (L::none(keep)) {  // no lane shades
            for (std::size_t k = 0; k < request.count; ++k) L::store_zero(out + k * n);
            continue;
        }
        position<V>(m, cells, angles, j, keep, g);
        if (request.stored) {
            for (std::size_t k = 0; k < request.count; ++k) store_values(value_of(m, g, SameChannel<V>{k}), g.cos_o, keep, out + k * n);
            continue;
        }
        const BatchWavelengths& wl = request.wavelengths;
        for (std::size_t k = 0; k < request.count; ++k) {
            alignas(32) std::int32_t c0[kLanes], c1[kLanes];
            alignas(32) typename L::Scalar t[kLanes];
            for (std::size_t lane = 0; lane < kLanes; ++lane) {
                const float* nm = wl.nm + (wl.per_pair ? (first + j + lane) * request.count : 0);
                std::uint32_t i0, i1;
                float tf;
                request.locator->locate(nm[k], i0, i1, tf);
                c0[lane] = std::int32_t(i0), c1[lane] = std::int32_t(i1), t[lane] = typename L::Scalar(tf);
            }
            const V tv = L::load(t);
            const V a = value_of(m, g, LaneChannels<V>{L::load_index(c0)});
            const V b = value_of(m, g, LaneChannels<V>{L::load_index(c1)});
            // (1 - t) a + t b, and a itself where t is 0 (as write_values, which skips b there).
            const V v = simd::select(tv == V(0.0), a, (V(1.0) - tv) * a + tv * b);
            store_values(v, g.cos_o, keep, out + k * n);
        }
    }
    return j;
}

}  // namespace

std::size_t values_avx2(const NpfModel& m, const CellMajorBases& cells, const BlockAngles& angles, std::size_t count,
                        const std::uint8_t* valid, const ValueRequestOfBlock& request, std::size_t first, float* values,
                        std::size_t n) {
    return values_of<Double4>(m, cells, angles, count, valid, request, first, values, n);
}

std::size_t values_float_avx2(const NpfModel& m, const CellMajorBases& cells, const BlockAnglesOf<float>& angles,
                              std::size_t count, const std::uint8_t* valid, const ValueRequestOfBlock& request,
                              std::size_t first, float* values, std::size_t n) {
    return values_of<Float8>(m, cells, angles, count, valid, request, first, values, n);
}

}  // namespace npf::batch_detail

#else

namespace npf::batch_detail {

std::size_t values_avx2(const NpfModel&, const CellMajorBases&, const BlockAngles&, std::size_t, const std::uint8_t*,
                        const ValueRequestOfBlock&, std::size_t, float*, std::size_t) {
    return 0;  // no vector path in this build: the caller shades every pair
}

std::size_t values_float_avx2(const NpfModel&, const CellMajorBases&, const BlockAnglesOf<float>&, std::size_t,
                              const std::uint8_t*, const ValueRequestOfBlock&, std::size_t, float*, std::size_t) {
    return 0;
}

}  // namespace npf::batch_detail

#endif
