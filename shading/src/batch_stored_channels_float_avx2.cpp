// The float lanes' path for a model's stored channels (BatchPrecision::Float; RGB, or up to four
// channels): every table looked up in each channel's own copy (channel_tables_of, paired cells),
// so that one load of eight floats per lane (two for an anisotropic table, four for the detail
// layer's corners) gives all channels at once, and no sum over ranks is left per value. The
// general float lanes (values_of in batch_values_avx2.cpp) cover spectral requests and models
// without these copies. Compiled with FMA and contracted multiply-adds like the other float
// kernels (CMakeLists.txt): within the float budget of docs/shading.md, not to the bit.
#include "batch_values.h"

#if defined(__AVX2__)
#include "batch_lanes_avx2.h"

#include <npf/shading/npf_equation.h>

namespace npf::batch_detail {

namespace {

using lanes::Lanes;
using simd::Float8;
using table::LerpOf;
using L = Lanes<Float8>;

// The four channels of a paired copy (paired_cells_of) at (row, col): one load per lane where
// the table has one column (rows side by side), else two (columns side by side, in rows i0 and
// i1), then the interpolation.
template <bool TwoAxes>
NPF_GENERIC_INLINE void channels_at(const float* paired, const LerpOf<Float8>& row, const LerpOf<Float8>& col, int cols,
                                    Float8 out[4]) {
    Float8 a[8];
    if (!TwoAxes) {
        L::columns8(paired, 4, simd::to_int32(row.i0), a);
        for (int c = 0; c < 4; ++c) out[c] = a[c] + row.t * (a[4 + c] - a[c]);
        return;
    }
    const Float8 padded = Float8(double(cols + 1));
    Float8 b[8];
    L::columns8(paired, 4, simd::to_int32(row.i0 * padded + col.i0), a);
    L::columns8(paired, 4, simd::to_int32(row.i1 * padded + col.i0), b);
    for (int c = 0; c < 4; ++c) {
        const Float8 lower = a[c] + col.t * (a[4 + c] - a[c]), upper = b[c] + col.t * (b[4 + c] - b[c]);
        out[c] = lower + row.t * (upper - lower);
    }
}

// The detail layer's residual of the four channels (padded_detail_cells_of).
NPF_GENERIC_INLINE void detail_at(const DetailGrid& grid, const float* padded, const std::size_t offset[4], Float8 u_h,
                                  Float8 theta_d, Float8 phi_d, Float8 out[4]) {
    LerpOf<Float8> h, d, p;
    detail_position_of(grid, u_h, theta_d, phi_d, h, d, p);
    L::padded_detail_ranks(grid, padded, offset, h, d, p, out);
}

template <bool DAzimuth, bool GAzimuth, bool Detail>
std::size_t stored_channels(const NpfModel& m, const CellMajorBases& cells, const BlockAnglesOf<float>& a, std::size_t count,
                            const std::uint8_t* valid, std::size_t first, float* values, std::size_t n) {
    const std::size_t channels = m.channel_count();
    Float8 rho_d[4], rho_s[4];
    for (std::size_t c = 0; c < channels; ++c) rho_d[c] = Float8(double(m.rho_d[c])), rho_s[c] = Float8(double(m.rho_s[c]));
    std::size_t offset[4] = {0, 0, 0, 0};
    if (Detail) detail_corner_offsets(m.detail_grid, offset);
    const LerpOf<Float8> one_column{Float8(0.0), Float8(0.0), Float8(0.0)};
    // The model's sizes and tables in locals, which the loop can keep in registers (the stores of
    // values could, for all the compiler knows, change the model's own fields).
    const int d_theta = m.d_theta, d_phi = m.d_phi, f_theta = m.f_theta, g_theta = m.g_theta, g_phi = m.g_phi;
    const DetailGrid grid = m.detail_grid;
    const float *d_cells = cells.channel_d, *f_cells = cells.f, *g_cells = cells.channel_g, *detail_cells = cells.channel_detail;
    std::size_t j = 0;
    for (; j + 8 <= count; j += 8) {
        const L::Keep keep = L::keep_of(valid + j);
        float* out = values + first + j;
        if (L::none(keep)) {
            for (std::size_t c = 0; c < channels; ++c) L::store_zero(out + c * n);
            continue;
        }
        // Lanes outside the domain look up at angles 0 (valid cells); their values are zeroed.
        auto at = [&](const float* field) { return L::keep(keep, L::load(field + j)); };
        const Float8 u_h = at(a.u_h), theta_d = at(a.theta_d);
        Float8 d[4], f[4], g_i[4], g_o[4], r[4];
        channels_at<DAzimuth>(d_cells, equation::d_row_of(u_h, d_theta), DAzimuth ? equation::column_of(at(a.phi_h), d_phi) : one_column,
                              d_phi, d);
        channels_at<false>(f_cells, equation::f_row_of(theta_d, f_theta), one_column, 1, f);
        channels_at<GAzimuth>(g_cells, equation::g_row_of(at(a.theta_gi), g_theta),
                              GAzimuth ? equation::column_of(at(a.phi_gi), g_phi) : one_column, g_phi, g_i);
        channels_at<GAzimuth>(g_cells, equation::g_row_of(at(a.theta_go), g_theta),
                              GAzimuth ? equation::column_of(at(a.phi_go), g_phi) : one_column, g_phi, g_o);
        if (Detail) detail_at(grid, detail_cells, offset, u_h, theta_d, at(a.phi_d), r);
        const Float8 cos_o = at(a.cos_o), inv_cos_product = at(a.inv_cos_product);
        for (std::size_t c = 0; c < channels; ++c) {
            Float8 v = equation::value_of<Float8>(rho_d[c], rho_s[c], d[c], f[c], g_i[c], g_o[c], inv_cos_product);
            if (Detail) v = equation::with_detail_of<Float8>(v, r[c]);
            lanes::store_values(v, cos_o, keep, out + c * n);
        }
    }
    return j;
}

}  // namespace

bool stored_channels_float_apply(const NpfModel& m, const CellMajorBases& cells, const ValueRequestOfBlock& request) {
    return request.stored && m.channel_count() <= 4 && cells.channel_d && cells.channel_g && cells.f &&
           (m.detail.rank == 0 || cells.channel_detail);
}

std::size_t stored_channels_float_avx2(const NpfModel& m, const CellMajorBases& cells, const BlockAnglesOf<float>& angles,
                                       std::size_t count, const std::uint8_t* valid, std::size_t first, float* values,
                                       std::size_t n) {
    const int k = (m.d_phi > 1 ? 4 : 0) + (m.g_phi > 1 ? 2 : 0) + (m.detail.rank > 0 ? 1 : 0);
    switch (k) {
    case 0: return stored_channels<false, false, false>(m, cells, angles, count, valid, first, values, n);
    case 1: return stored_channels<false, false, true>(m, cells, angles, count, valid, first, values, n);
    case 2: return stored_channels<false, true, false>(m, cells, angles, count, valid, first, values, n);
    case 3: return stored_channels<false, true, true>(m, cells, angles, count, valid, first, values, n);
    case 4: return stored_channels<true, false, false>(m, cells, angles, count, valid, first, values, n);
    case 5: return stored_channels<true, false, true>(m, cells, angles, count, valid, first, values, n);
    case 6: return stored_channels<true, true, false>(m, cells, angles, count, valid, first, values, n);
    default: return stored_channels<true, true, true>(m, cells, angles, count, valid, first, values, n);
    }
}

}  // namespace npf::batch_detail

#else

namespace npf::batch_detail {

bool stored_channels_float_apply(const NpfModel&, const CellMajorBases&, const ValueRequestOfBlock&) { return false; }

std::size_t stored_channels_float_avx2(const NpfModel&, const CellMajorBases&, const BlockAnglesOf<float>&, std::size_t,
                                       const std::uint8_t*, std::size_t, float*, std::size_t) {
    return 0;
}

}  // namespace npf::batch_detail

#endif
