// The batched eval's table lookups for AVX2 (batch_values.h): four pairs per step. Compiled with
// -mavx2 and without FMA (CMakeLists.txt), called only where the CPU has AVX2 (npf_batch.cpp).
// Every sum below is NpfModel::position's and NpfModel::value's, term for term in their order,
// so that each lane gets the scalar closure's bits (tests/test_batch_closure.cpp).
#include "batch_values.h"

#if defined(__AVX2__)
#include "simd_double4.h"

#include <npf/shading/npf_equation.h>

namespace npf::batch_detail {

namespace {

using simd::Double4;
using table::LerpOf;

// The interpolated basis values of one table at four pairs: gathers from each basis table.
struct Corners4 {
    __m128i index[4];
    Double4 weight[4];
    bool one_column;  // corners 1 and 3 are corners 0 and 2 (a table of one column): gathered once
};

Corners4 bilinear4(const LerpOf<Double4>& row, const LerpOf<Double4>& col, int cols) {
    const Double4 c = Double4(double(cols));
    const Double4 r0 = row.i0 * c, r1 = row.i1 * c;
    Corners4 k;
    k.index[0] = simd::to_int32(r0 + col.i0);
    k.index[1] = simd::to_int32(r0 + col.i1);
    k.index[2] = simd::to_int32(r1 + col.i0);
    k.index[3] = simd::to_int32(r1 + col.i1);
    table::generic::bilinear_weights<Double4>(row.t, col.t, k.weight);
    k.one_column = cols == 1;
    return k;
}

// Ranks 0..3 of cell index[lane] of a cell-major table (cell_major_of) for each lane: one load per
// lane, then a transpose, so that ranks[r] holds rank r of the four lanes (as gather would).
void corner_ranks(const float* cells, __m128i index, Double4 ranks[4]) {
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

// The bilinear value of each rank at four pairs: from the cell-major copy where there is one
// (the same products and sums, so the same bits), else gathered rank by rank.
void project4(const SpectralBasis& s, const float* cell_major, const Corners4& k, Double4* out) {
    if (cell_major) {
        Double4 c0[4], c1[4], c2[4], c3[4];
        corner_ranks(cell_major, k.index[0], c0);
        corner_ranks(cell_major, k.index[2], c2);
        if (k.one_column) {
            for (int r = 0; r < s.rank; ++r) out[r] = c0[r] * k.weight[0] + c0[r] * k.weight[1] + c2[r] * k.weight[2] + c2[r] * k.weight[3];
            return;
        }
        corner_ranks(cell_major, k.index[1], c1);
        corner_ranks(cell_major, k.index[3], c3);
        for (int r = 0; r < s.rank; ++r) out[r] = c0[r] * k.weight[0] + c1[r] * k.weight[1] + c2[r] * k.weight[2] + c3[r] * k.weight[3];
        return;
    }
    const float* t = s.basis.data();
    if (k.one_column) {
        for (int r = 0; r < s.rank; ++r, t += s.cells) {
            const Double4 v0 = simd::gather(t, k.index[0]), v2 = simd::gather(t, k.index[2]);
            out[r] = v0 * k.weight[0] + v0 * k.weight[1] + v2 * k.weight[2] + v2 * k.weight[3];
        }
        return;
    }
    for (int r = 0; r < s.rank; ++r, t += s.cells) {
        out[r] = simd::gather(t, k.index[0]) * k.weight[0] + simd::gather(t, k.index[1]) * k.weight[1] +
                 simd::gather(t, k.index[2]) * k.weight[2] + simd::gather(t, k.index[3]) * k.weight[3];
    }
}

// What every channel of four pairs shares (NpfModel::Lookup, as vectors).
struct Group {
    Double4 cos_o, inv_cos_product, f_t;
    __m128i f0, f1;
    Double4 d[kVectorRank], g_i[kVectorRank], g_o[kVectorRank], r[kVectorRank];
};

Double4 select_lanes(__m256d keep, Double4 a) { return Double4(_mm256_and_pd(keep, a.v)); }

LerpOf<Double4> g_column(Double4 phi, int g_phi) {
    if (g_phi == 1) return {Double4(0.0), Double4(0.0), Double4(0.0)};
    return equation::column_of(phi, g_phi);
}

// NpfModel::position for pairs j .. j + 3 of the block; lanes outside the domain (keep false)
// look up at angles 0 (valid cells; their values are zeroed later).
void position4(const NpfModel& m, const CellMajorBases& cells, const BlockAngles& a, std::size_t j, __m256d keep, Group& g) {
    auto at = [&](const double* field) { return select_lanes(keep, simd::load4(field + j)); };
    g.cos_o = at(a.cos_o);
    g.inv_cos_product = at(a.inv_cos_product);
    const Double4 u_h = at(a.u_h), theta_d = at(a.theta_d);
    project4(m.D, cells.d, bilinear4(equation::d_row_of(u_h, m.d_theta), equation::column_of(at(a.phi_h), m.d_phi), m.d_phi), g.d);
    const LerpOf<Double4> f = equation::f_row_of(theta_d, m.f_theta);
    g.f0 = simd::to_int32(f.i0);
    g.f1 = simd::to_int32(f.i1);
    g.f_t = f.t;
    project4(m.G, cells.g, bilinear4(equation::g_row_of(at(a.theta_gi), m.g_theta), g_column(at(a.phi_gi), m.g_phi), m.g_phi), g.g_i);
    project4(m.G, cells.g, bilinear4(equation::g_row_of(at(a.theta_go), m.g_theta), g_column(at(a.phi_go), m.g_phi), m.g_phi), g.g_o);
    if (!m.has_detail()) return;
    const DetailGrid& grid = m.detail_grid;
    LerpOf<Double4> h, d, p;
    detail_position_of(grid, u_h, theta_d, at(a.phi_d), h, d, p);
    Double4 weight[8];
    trilinear_weights<Double4>(h.t, d.t, p.t, weight);
    __m128i index[8];
    const Double4 rows = Double4(double(grid.theta_d)), cols = Double4(double(grid.phi_d));
    for (int k = 0; k < 8; ++k) {
        const Double4 hi = k & 4 ? h.i1 : h.i0, di = k & 2 ? d.i1 : d.i0, pi = k & 1 ? p.i1 : p.i0;
        index[k] = simd::to_int32((hi * rows + di) * cols + pi);
    }
    if (cells.detail) {  // corner by corner, each rank's sum in the same order as below
        for (int r = 0; r < m.detail.rank; ++r) g.r[r] = Double4(0.0);
        for (int k = 0; k < 8; ++k) {
            Double4 c[4];
            corner_ranks(cells.detail, index[k], c);
            for (int r = 0; r < m.detail.rank; ++r) g.r[r] = g.r[r] + c[r] * weight[k];
        }
        return;
    }
    const float* b = m.detail.basis.data();
    for (int r = 0; r < m.detail.rank; ++r, b += m.detail.cells) {
        Double4 v(0.0);
        for (int k = 0; k < 8; ++k) v = v + simd::gather(b, index[k]) * weight[k];
        g.r[r] = v;
    }
}

// The channel of each lane: one for all (stored channels, shared wavelengths), or per lane.
struct SameChannel {
    std::size_t c;
    Double4 weight(const std::vector<float>& w, int rank, int k) const { return Double4(double(w[c * std::size_t(rank) + std::size_t(k)])); }
    Double4 of(const std::vector<float>& v) const { return Double4(double(v[c])); }
    Double4 f(const NpfModel& m, __m128i cell) const { return simd::gather(m.F.data() + c * std::size_t(m.f_theta), cell); }
};
struct LaneChannels {
    __m128i c;
    Double4 weight(const std::vector<float>& w, int rank, int k) const {
        return simd::gather(w.data(), _mm_add_epi32(_mm_mullo_epi32(c, _mm_set1_epi32(rank)), _mm_set1_epi32(k)));
    }
    Double4 of(const std::vector<float>& v) const { return simd::gather(v.data(), c); }
    Double4 f(const NpfModel& m, __m128i cell) const {
        return simd::gather(m.F.data(), _mm_add_epi32(_mm_mullo_epi32(c, _mm_set1_epi32(m.f_theta)), cell));
    }
};

// NpfModel::value, term for term.
template <class Channel>
Double4 value4(const NpfModel& m, const Group& g, const Channel& c) {
    Double4 d(0.0), gi(0.0), go(0.0);
    for (int k = 0; k < m.D.rank; ++k) d = d + c.weight(m.D.weights, m.D.rank, k) * g.d[k];
    for (int k = 0; k < m.G.rank; ++k) {
        const Double4 w = c.weight(m.G.weights, m.G.rank, k);
        gi = gi + w * g.g_i[k];
        go = go + w * g.g_o[k];
    }
    const Double4 fv = c.f(m, g.f0) * (Double4(1.0) - g.f_t) + c.f(m, g.f1) * g.f_t;
    const Double4 base = equation::value_of<Double4>(c.of(m.rho_d), c.of(m.rho_s), d, fv, gi, go, g.inv_cos_product);
    if (m.detail.rank == 0) return base;
    Double4 r(0.0);
    for (int k = 0; k < m.detail.rank; ++k) r = r + c.weight(m.detail.weights, m.detail.rank, k) * g.r[k];
    return equation::with_detail_of<Double4>(base, r);
}

// NpfClosure::write_values' last step: finite_float(max(0, v) cos_light), then 0 outside the domain.
void store4(Double4 v, Double4 cos_light, __m256d keep, float* out) {
    v = simd::select(Double4(0.0) < v, v, Double4(0.0)) * cos_light;
    _mm_storeu_ps(out, _mm256_cvtpd_ps(select_lanes(keep, simd::finite_float_of(v)).v));
}

}  // namespace

std::size_t values_avx2(const NpfModel& m, const CellMajorBases& cells, const BlockAngles& angles, std::size_t count,
                        const std::uint8_t* valid, const ValueRequestOfBlock& request, std::size_t first, float* values,
                        std::size_t n) {
    Group g;
    std::size_t j = 0;
    for (; j + 4 <= count; j += 4) {
        const __m256d keep = _mm256_castsi256_pd(
            _mm256_set_epi64x(-std::int64_t(valid[j + 3] != 0), -std::int64_t(valid[j + 2] != 0),
                              -std::int64_t(valid[j + 1] != 0), -std::int64_t(valid[j] != 0)));
        float* out = values + first + j;
        if (_mm256_testz_pd(keep, keep)) {  // no lane shades
            for (std::size_t k = 0; k < request.count; ++k) _mm_storeu_ps(out + k * n, _mm_setzero_ps());
            continue;
        }
        position4(m, cells, angles, j, keep, g);
        if (request.stored) {
            for (std::size_t k = 0; k < request.count; ++k) store4(value4(m, g, SameChannel{k}), g.cos_o, keep, out + k * n);
            continue;
        }
        const BatchWavelengths& wl = request.wavelengths;
        for (std::size_t k = 0; k < request.count; ++k) {
            alignas(16) std::int32_t c0[4], c1[4];
            alignas(32) double t[4];
            for (int lane = 0; lane < 4; ++lane) {
                const float* nm = wl.nm + (wl.per_pair ? (first + j + std::size_t(lane)) * request.count : 0);
                std::uint32_t i0, i1;
                float tf;
                request.locator->locate(nm[k], i0, i1, tf);
                c0[lane] = std::int32_t(i0), c1[lane] = std::int32_t(i1), t[lane] = double(tf);
            }
            const Double4 tv = simd::load4(t);
            const Double4 a = value4(m, g, LaneChannels{_mm_load_si128(reinterpret_cast<const __m128i*>(c0))});
            const Double4 b = value4(m, g, LaneChannels{_mm_load_si128(reinterpret_cast<const __m128i*>(c1))});
            // (1 - t) a + t b, and a itself where t is 0 (as write_values, which skips b there).
            const Double4 v = simd::select(tv == Double4(0.0), a, (Double4(1.0) - tv) * a + tv * b);
            store4(v, g.cos_o, keep, out + k * n);
        }
    }
    return j;
}

}  // namespace npf::batch_detail

#else

namespace npf::batch_detail {

std::size_t values_avx2(const NpfModel&, const CellMajorBases&, const BlockAngles&, std::size_t, const std::uint8_t*,
                        const ValueRequestOfBlock&, std::size_t, float*, std::size_t) {
    return 0;  // no vector path in this build: the caller shades every pair
}

}  // namespace npf::batch_detail

#endif
