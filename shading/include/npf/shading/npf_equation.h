// The NPF model in one place: paper Eq. 1 and the geometry of its tables (docs/format.md sec. 3).
// The fitter (converter/fit), its error and energy checks, the stored model (NpfModel), the
// texture path (NpfClosure) and the edits all take the equation, the axis maps and G's horizon
// rule from here, so a file evaluates exactly as the fit that wrote it, and a change to the model
// is made once.
//
//   f_r(wi, wo) = rho_d + rho_s D(theta_h, phi_h) F(theta_d) G(theta_i, phi_i) G(theta_o, phi_o)
//                 / (cos theta_i cos theta_o)                                          (Eq. 1)
//   with the optional detail layer: max(0, f_r + r(u_h, theta_d, phi_d))
//
// Table axes, each in cells of its table (cell k's centre at k + 1/2; table_interpolation.h):
//   D rows     u_h = sqrt(theta_h / (pi/2)) in [0, 1]   (dense near the specular peak), clamped
//   F rows     theta_d / (pi/2)                          clamped
//   G rows     theta / (pi/2)                            beyond the last centre: the line through
//                                                        the last two rows (the horizon rule)
//   columns    phi / (2 pi) (phi_h of D, phi of G)       periodic; one column: isotropic
#pragma once

#include <npf/core/vec.h>
#include <npf/shading/table_interpolation.h>

namespace npf::equation {

// The equation's names for npf::kHalfPiD and npf::kTwoPiD (core/vec.h), not other values.
constexpr double kHalfPi = kHalfPiD, kTwoPi = kTwoPiD;
// Multiplications by these rather than divisions: the shading hot path has a dozen per pair.
constexpr double kInvHalfPi = 1.0 / kHalfPi, kInvTwoPi = 1.0 / kTwoPi;

// ---- D's square-root map ---------------------------------------------------------------------
inline double u_of_theta_h(double theta_h) { return std::sqrt(theta_h * kInvHalfPi); }
// The same for any number type of table::generic (the batched closure's vectors).
template <class T>
NPF_GENERIC_INLINE T u_of_theta_h_generic(T theta_h) {
    using table::generic::sqrt;
    return sqrt(theta_h * T(kInvHalfPi));
}
inline double theta_h_of_u(double u) { return kHalfPi * u * u; }

// ---- Cell centres (the fitter's sample positions and the tables' value positions) -------------
inline double theta_h_centre(int k, int n) { return theta_h_of_u((k + 0.5) / n); }  // D rows
inline double theta_centre(int k, int n) { return kHalfPi * (k + 0.5) / n; }         // F and G rows
inline double phi_centre(int k, int n) { return kTwoPi * (k + 0.5) / n; }            // columns

// ---- Where an angle falls on each table (cells, with the axis' boundary rule) ----------------
// Generic over the number type (table::generic) for the batched closure; the scalar forms below.
// A polar angle in cells of an n-row table uniform in theta (F and G rows).
template <class T>
NPF_GENERIC_INLINE T theta_cells_of(T theta, int n) { return theta * T(kInvHalfPi) * T(double(n)); }
template <class T>
NPF_GENERIC_INLINE table::LerpOf<T> d_row_of(T u_h, int n) { return table::generic::clamped(u_h * T(double(n)), n); }
template <class T>
NPF_GENERIC_INLINE table::LerpOf<T> f_row_of(T theta_d, int n) { return table::generic::clamped(theta_cells_of(theta_d, n), n); }
template <class T>
NPF_GENERIC_INLINE table::LerpOf<T> g_row_of(T theta, int n) { return table::generic::extrapolated(theta_cells_of(theta, n), n); }
template <class T>
NPF_GENERIC_INLINE table::LerpOf<T> column_of(T phi, int n) { return table::generic::periodic(phi * T(kInvTwoPi) * T(double(n)), n); }

inline double theta_cells(double theta, int n) { return theta_cells_of<double>(theta, n); }
inline table::Lerp d_row(double u_h, int n) { return table::to_lerp(d_row_of<double>(u_h, n)); }
inline table::Lerp f_row(double theta_d, int n) { return table::to_lerp(f_row_of<double>(theta_d, n)); }
inline table::Lerp g_row(double theta, int n) { return table::to_lerp(g_row_of<double>(theta, n)); }
// With one column (isotropic) every position gives that column: callers may skip the azimuth
// and use Lerp{} (the same value).
inline table::Lerp column(double phi, int n) { return table::to_lerp(column_of<double>(phi, n)); }
// The G row a direction of polar angle theta belongs to (the cell holding it, not its centre).
inline int g_owner_row(double theta, int n) { return std::min(int(theta_cells(theta, n)), n - 1); }

// ---- G's horizon rule -------------------------------------------------------------------------
// Beyond the last row's centre G continues along the line through the last two rows: at x cells
// past the last centre (x = 1/2 at the horizon itself) the value is last + x (last - prev). Where
// that stays above 0 at the horizon, the albedo grows like 1 / cos(theta_view) in the last fraction
// of a degree (silhouettes gain light without bound); it reaches 0 there when last <= prev / 3.
inline double g_beyond_last_row(double last, double prev, double x) { return last + x * (last - prev); }
inline double g_at_horizon(double last, double prev) { return g_beyond_last_row(last, prev, 0.5); }
// The largest factor on the last row that closes G at the horizon (g_at_horizon(last s, prev) = 0).
inline double g_closing_scale(double last, double prev) { return last > 0.0 ? std::max(0.0, prev / (3.0 * last)) : 0.0; }

// ---- Eq. 1 ------------------------------------------------------------------------------------
// The factors as interpolated (D, G possibly recombined from a spectral basis, so clamped at 0
// here); inv_cos_product = 1 / (cos theta_i cos theta_o).
// Generic over the number type (table::generic), for the batched closure.
template <class T>
NPF_GENERIC_INLINE T value_of(T rho_d, T rho_s, T d, T f, T g_i, T g_o, T inv_cos_product) {
    using table::generic::select;
    d = select(d > T(0.0), d, T(0.0));
    g_i = select(g_i > T(0.0), g_i, T(0.0));
    g_o = select(g_o > T(0.0), g_o, T(0.0));
    return rho_d + rho_s * d * f * g_i * g_o * inv_cos_product;
}
inline double value(double rho_d, double rho_s, double d, double f, double g_i, double g_o, double inv_cos_product) {
    return value_of<double>(rho_d, rho_s, d, f, g_i, g_o, inv_cos_product);
}
// The detail layer's residual added to the model's value; the sum is clamped at 0.
template <class T>
NPF_GENERIC_INLINE T with_detail_of(T base, T residual) {
    using table::generic::select;
    const T v = base + residual;
    return select(v > T(0.0), v, T(0.0));
}
inline double with_detail(double base, double residual) { return with_detail_of<double>(base, residual); }

}  // namespace npf::equation
