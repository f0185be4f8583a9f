#include <npf/fit/npf_factors.h>

#include <npf/core/vec.h>
#include <npf/shading/npf_equation.h>
#include <npf/shading/table_interpolation.h>

#include <algorithm>
#include <cmath>

namespace npf {

namespace {

using table::Lerp;

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
    // The stored model's axes and horizon rule (npf_equation.h), on full per-channel tables.
    const double dv = table2(d, grid.phi_h, equation::d_row(equation::u_of_theta_h(a.theta_h), grid.theta_h),
                             equation::column(a.phi_h, grid.phi_h));
    const Lerp fl = equation::f_row(a.theta_d, grid.theta_d);
    const double fv = f[fl.i0] * (1 - fl.t) + f[fl.i1] * fl.t;
    auto gv = [&](const Vec3d& w) {
        return table2(g, g_phi, equation::g_row(table::polar(w.x, w.y, w.z), g_theta),
                      equation::column(table::azimuth(w.x, w.y), g_phi));
    };
    return equation::value(rho_d[c], rho_s[c], dv, fv, gv(wi), gv(wo), 1.0 / (wi.z * wo.z));
}

}  // namespace npf
