// The detail layer's grid (docs/format.md sec. 2 and 3): an additive residual r_c over three of
// Rusinkiewicz's angles, added to the NPF model's value where the separable factors cannot follow
// the measurement:
//   f_r = max(0, NPF(wi, wo) + r_c(u_h, theta_d, phi_d))
// with u_h = sqrt(theta_h / (pi/2)) (the D table's square-root map: dense at the specular peak),
// theta_d and phi_d of wi (the conditioning, viewer-side direction) in the frame of the half
// vector, phi_d over the whole [0, 2 pi): measured materials are not reciprocal near grazing, and
// a residual folded to [0, pi) cannot hold that (docs/fitting.md, "Detail layer").
//
// Cells are indexed [theta_h][theta_d][phi_d], values at cell centres ((k + 1/2) / n of each
// axis' unit range), trilinear between centres, clamped in u_h and theta_d, periodic in phi_d.
// One definition for the fitter (converter/fit/detail_fit), the stored model (NpfModel) and the
// texture path, so that a file shades exactly as its fit.
#pragma once

#include <npf/core/vec.h>
#include <npf/shading/npf_equation.h>
#include <npf/shading/table_interpolation.h>

#include <cstddef>
#include <cstdint>

namespace npf {

struct DetailGrid {
    int theta_h = 0, theta_d = 0, phi_d = 0;  // all 0: no detail layer

    bool empty() const { return theta_h <= 0 || theta_d <= 0 || phi_d <= 0; }
    std::size_t cells() const { return empty() ? 0 : std::size_t(theta_h) * std::size_t(theta_d) * std::size_t(phi_d); }
    std::size_t index(int h, int d, int p) const {
        return (std::size_t(h) * std::size_t(theta_d) + std::size_t(d)) * std::size_t(phi_d) + std::size_t(p);
    }
    bool operator==(const DetailGrid& o) const {
        return theta_h == o.theta_h && theta_d == o.theta_d && phi_d == o.phi_d;
    }
    bool operator!=(const DetailGrid& o) const { return !(*this == o); }
};

// The eight corners around a position and their weights.
struct Trilinear {
    std::uint32_t index[8];
    double weight[8];
};

// Where a position falls on each axis (cells, centres at integers), for lookups that interpolate
// elsewhere (a texture): h and d clamped to [0, n - 1], p in [0, n).
struct DetailPosition {
    table::Lerp h, d, p;
};

// The rows of D and F and a periodic column (npf_equation.h), over the residual's own grid;
// generic over the number type (table::generic) for the batched closure.
template <class T>
NPF_GENERIC_INLINE void detail_position_of(const DetailGrid& g, T u_h, T theta_d, T phi_d, table::LerpOf<T>& h,
                                           table::LerpOf<T>& d, table::LerpOf<T>& p) {
    h = equation::d_row_of(u_h, g.theta_h);
    d = equation::f_row_of(theta_d, g.theta_d);
    p = equation::column_of(phi_d, g.phi_d);
}

inline DetailPosition detail_position(const DetailGrid& g, double u_h, double theta_d, double phi_d) {
    table::LerpOf<double> h, d, p;
    detail_position_of<double>(g, u_h, theta_d, phi_d, h, d, p);
    return {table::to_lerp(h), table::to_lerp(d), table::to_lerp(p)};
}

// The weights of the eight corners, corner k = 4 a + 2 b + c taking the upper cell along h
// where a is 1, along d where b is 1, along p where c is 1.
template <class T>
NPF_GENERIC_INLINE void trilinear_weights(T h_t, T d_t, T p_t, T w[8]) {
    for (int a = 0; a < 2; ++a) {
        const T wh = a ? h_t : T(1.0) - h_t;
        for (int b = 0; b < 2; ++b) {
            const T wd = wh * (b ? d_t : T(1.0) - d_t);
            for (int c = 0; c < 2; ++c) w[4 * a + 2 * b + c] = wd * (c ? p_t : T(1.0) - p_t);
        }
    }
}

inline Trilinear trilinear(const DetailGrid& g, const DetailPosition& at) {
    Trilinear t;
    const table::Lerp& h = at.h;
    const table::Lerp& d = at.d;
    const table::Lerp& p = at.p;
    for (int k = 0; k < 8; ++k) {
        t.index[k] = std::uint32_t(g.index(k & 4 ? h.i1 : h.i0, k & 2 ? d.i1 : d.i0, k & 1 ? p.i1 : p.i0));
    }
    trilinear_weights<double>(h.t, d.t, p.t, t.weight);
    return t;
}

// phi_d of the pair: the azimuth of wi in the frame of the half vector (wi rotated by -phi_h about
// the normal, then by -theta_h about the bitangent), in [0, 2 pi). (hx, hy, hz) = wi + wo, not
// normalised; `length` is its length. At the pole (h along the normal) phi_h is taken as 0.
template <class T>
NPF_GENERIC_INLINE T detail_phi_d_generic(T ix, T iy, T iz, T hx, T hy, T hz, T length) {
    using table::generic::select;
    const T r2 = hx * hx + hy * hy;
    // d scaled by r |H| > 0, which leaves its azimuth unchanged:
    //   d_x = cos theta_h (cos phi_h ix + sin phi_h iy) - sin theta_h iz,  d_y = -sin phi_h ix + cos phi_h iy.
    const T dx = hz * (hx * ix + hy * iy) - r2 * iz;
    const T dy = length * (hx * iy - hy * ix);
    // h along the normal: wi's own azimuth. A select, not a branch, so that batches vectorise.
    const auto along_normal = !(r2 > T(1e-24) * length * length);
    return table::generic::azimuth(select(along_normal, ix, dx), select(along_normal, iy, dy));
}
inline double detail_phi_d(double ix, double iy, double iz, double hx, double hy, double hz, double length) {
    return detail_phi_d_generic<double>(ix, iy, iz, hx, hy, hz, length);
}

}  // namespace npf
