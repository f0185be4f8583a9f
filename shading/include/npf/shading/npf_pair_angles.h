// The angles a direction pair is looked up by (the first half of NpfModel::prepare): one
// definition for the scalar evaluation and the batched one (npf_batch.h), generic over the number
// type (table::generic: `double`, or a vector of doubles), so that both compute the same values
// to the bit. Straight-line arithmetic with selects, no branches on the data.
#pragma once

#include <npf/shading/detail_grid.h>
#include <npf/shading/npf_equation.h>
#include <npf/shading/table_interpolation.h>

#include <cmath>

namespace npf {

// The pairs an evaluation answers (the scalar and the batched closure alike): both directions
// strictly above the horizon and every component finite. Elsewhere f_r and the pdf are 0.
inline bool pair_in_domain(const Vec3& wi, const Vec3& wo) {
    const auto finite = [](const Vec3& w) { return std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z); };
    return wi.z > 0.f && wo.z > 0.f && finite(wi) && finite(wo);
}

template <class T>
struct PairAnglesOf {
    T cos_i, cos_o, inv_cos_product;  // inv: 1 / (cos_i cos_o)
    T theta_h, u_h, phi_h, cos_d;     // the half vector (phi_h 0 for an isotropic D); cos_d = wi . h
    T theta_d;
    T theta_gi, phi_gi, theta_go, phi_go;  // wi and wo on G (phi 0 for an isotropic G)
    T phi_d;                               // the detail layer's azimuth (0 without one)
};
using PairAngles = PairAnglesOf<double>;

// Which azimuths a model needs: D's and G's only when anisotropic, the detail layer's only when
// present.
struct AngleNeeds {
    bool d_azimuth = false, g_azimuth = false, detail = false;
};

// The half vector's angles alone (what a pdf needs): those of H = wi + wo, with no
// normalisation on their path (a square root and a division less on the longest chain).
template <class T>
NPF_GENERIC_INLINE void half_vector_angles_of(T ix, T iy, T iz, T ox, T oy, T oz, bool d_azimuth, T& theta_h, T& u_h, T& phi_h, T& cos_d) {
    using table::generic::sqrt;
    const T hx = ix + ox, hy = iy + oy, hz = iz + oz;
    const T r2 = hx * hx + hy * hy;
    theta_h = table::generic::polar_of(sqrt(r2), hz);
    phi_h = d_azimuth ? table::generic::azimuth(hx, hy) : T(0.0);
    u_h = equation::u_of_theta_h_generic(theta_h);
    cos_d = (ix * hx + iy * hy + iz * hz) / sqrt(r2 + hz * hz);
}

// The angles of (wi, wo), wi the conditioned (view) direction; both above the horizon (the
// caller checks). theta_d, half the angle between wi and wo, is atan2(|wi x wo|, 1 + wi . wo),
// accurate at both ends and independent of h.
template <class T>
NPF_GENERIC_INLINE void pair_angles_of(T ix, T iy, T iz, T ox, T oy, T oz, AngleNeeds needs, PairAnglesOf<T>& a) {
    using table::generic::sqrt;
    a.cos_i = iz;
    a.cos_o = oz;
    half_vector_angles_of(ix, iy, iz, ox, oy, oz, needs.d_azimuth, a.theta_h, a.u_h, a.phi_h, a.cos_d);
    const T cx = iy * oz - iz * oy, cy = iz * ox - ix * oz, cz = ix * oy - iy * ox;
    a.theta_d = table::generic::polar_of(sqrt(cx * cx + cy * cy + cz * cz), T(1.0) + (ix * ox + iy * oy + iz * oz));
    a.inv_cos_product = T(1.0) / (iz * oz);
    a.theta_gi = table::generic::polar(ix, iy, iz);
    a.phi_gi = needs.g_azimuth ? table::generic::azimuth(ix, iy) : T(0.0);
    a.theta_go = table::generic::polar(ox, oy, oz);
    a.phi_go = needs.g_azimuth ? table::generic::azimuth(ox, oy) : T(0.0);
    const T hx = ix + ox, hy = iy + oy, hz = iz + oz;
    a.phi_d = needs.detail ? detail_phi_d_generic(ix, iy, iz, hx, hy, hz, sqrt(hx * hx + hy * hy + hz * hz)) : T(0.0);
}

// The scalar forms (double, whatever the caller's types).
inline void half_vector_angles(double ix, double iy, double iz, double ox, double oy, double oz, bool d_azimuth,
                               double& theta_h, double& u_h, double& phi_h, double& cos_d) {
    half_vector_angles_of<double>(ix, iy, iz, ox, oy, oz, d_azimuth, theta_h, u_h, phi_h, cos_d);
}
inline void pair_angles(double ix, double iy, double iz, double ox, double oy, double oz, AngleNeeds needs, PairAngles& a) {
    pair_angles_of<double>(ix, iy, iz, ox, oy, oz, needs, a);
}

}  // namespace npf
