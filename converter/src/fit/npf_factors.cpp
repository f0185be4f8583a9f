#include <npf/converter/fit/npf_factors.h>

#include <npf/core/vec.h>
#include <npf/shading/table_interpolation.h>

#include <algorithm>
#include <cmath>

namespace npf {

namespace {

constexpr double kHalfPi = 0.5 * kPiD, kTwoPi = 2.0 * kPiD;

using table::Lerp;
using table::clamped;
using table::periodic;

double table2(const float* t, int cols, const Lerp& r, const Lerp& c) {
    const double a = t[r.i0 * cols + c.i0] * (1 - c.t) + t[r.i0 * cols + c.i1] * c.t;
    const double b = t[r.i1 * cols + c.i0] * (1 - c.t) + t[r.i1 * cols + c.i1] * c.t;
    return a * (1 - r.t) + b * r.t;
}

}  // namespace

double NpfFactors::eval(std::size_t c, const Vec3d& wi, const Vec3d& wo) const {
    if (!(wi.z > 0.0) || !(wo.z > 0.0)) return 0.0;
    const HalfDiff a = half_diff_from_directions(wi, wo);
    const float* d = D.data() + c * d_size();
    const float* f = F.data() + c * std::size_t(grid.theta_d);
    const float* g = G.data() + c * g_size();
    const double u = std::sqrt(a.theta_h / kHalfPi);
    const double dv = table2(d, grid.phi_h, clamped(u * grid.theta_h, grid.theta_h),
                             periodic(a.phi_h / kTwoPi * grid.phi_h, grid.phi_h));
    const Lerp fl = clamped(a.theta_d / kHalfPi * grid.theta_d, grid.theta_d);
    const double fv = f[fl.i0] * (1 - fl.t) + f[fl.i1] * fl.t;
    // G: bilinear on its cell centres, extrapolated towards the horizon (table::extrapolated).
    auto gv = [&](const Vec3d& w) {
        const Lerp row = table::extrapolated(table::polar(w.x, w.y, w.z) / kHalfPi * g_theta, g_theta);
        const Lerp col = periodic(table::azimuth(w.x, w.y) / kTwoPi * g_phi, g_phi);
        return std::max(0.0, table2(g, g_phi, row, col));
    };
    return rho_d[c] + rho_s[c] * dv * fv * gv(wi) * gv(wo) / (wi.z * wo.z);
}

}  // namespace npf
