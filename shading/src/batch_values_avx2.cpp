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
#include "batch_lanes_avx2.h"

#include <npf/shading/npf_equation.h>


namespace npf::batch_detail {

namespace {

using simd::Double4;
using simd::Float8;
using table::LerpOf;
using lanes::Lanes;
using lanes::store_values;

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
// false) look up at angles 0 (valid cells; their values are zeroed later).
template <class V>
NPF_GENERIC_INLINE void position(const NpfModel& m, const CellMajorBases& cells, const BlockAnglesOf<typename Lanes<V>::Scalar>& a,
                                 std::size_t j, typename Lanes<V>::Keep keep, bool stored, Group<V>& g) {
    using L = Lanes<V>;
    const float* d_cells = cells.d;
    const float* g_cells = cells.g;
    const float* detail_cells = cells.detail;
    const int d_rank = m.D.rank, g_rank = m.G.rank, detail_rank = m.detail.rank;
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
    if (g.f_cells) {  // rows f0 and f0 + 1 side by side (f1 is one of them)
        V pair[8];
        L::columns8(cells.f, 4, g.f0, pair);
        for (int c = 0; c < 4; ++c) g.f_at0[c] = pair[c], g.f_at1[c] = pair[4 + c];
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
    if (detail_cells) {  // padded_detail_cells_of: corner pairs q = 2a + b at fixed offsets, cells p.i0 and p.i1 side by side
        std::size_t offset[4];
        detail_corner_offsets(grid, offset);
#if defined(NPF_BATCH_VALUES_FLOAT)
        V ranks[4];
        L::padded_detail_ranks(grid, detail_cells, offset, h, d, p, ranks);
        for (int r = 0; r < detail_rank; ++r) g.r[r] = ranks[r];
#else
        const V padded_rows = V(double(grid.theta_d + 1)), padded_cols = V(double(grid.phi_d + 1));
        const typename L::Index first = simd::to_int32((h.i0 * padded_rows + d.i0) * padded_cols + p.i0);
        V sum[4] = {V(0.0), V(0.0), V(0.0), V(0.0)};  // all four ranks, in registers (the copy pads with 0)
        for (int q = 0; q < 4; ++q) {  // each rank's sum in the scalar closure's order of the corners
            V c[8];
            L::columns8(detail_cells + 4 * offset[q], 4, first, c);
            for (int r = 0; r < 4; ++r) sum[r] = sum[r] + c[r] * weight[2 * q];
            for (int r = 0; r < 4; ++r) sum[r] = sum[r] + c[4 + r] * weight[2 * q + 1];
        }
        for (int r = 0; r < detail_rank; ++r) g.r[r] = sum[r];
#endif
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
        position<V>(m, cells, angles, j, keep, request.stored, g);
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
    if (stored_channels_float_apply(m, cells, request))
        return stored_channels_float_avx2(m, cells, angles, count, valid, first, values, n);
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
