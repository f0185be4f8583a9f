#include <npf/converter/fit/npf_factors.h>

#include <npf/core/vec.h>

#include <algorithm>
#include <cmath>

namespace npf {

namespace {

constexpr double kHalfPi = 0.5 * kPiD, kTwoPi = 2.0 * kPiD;

// Linear interpolation position on cell centres: x in cell units (centre of cell k at k + 1/2).
struct Lerp {
    int i0 = 0, i1 = 0;
    double t = 0.0;
};

Lerp clamped(double x, int n) {
    Lerp l;
    const double c = std::clamp(x - 0.5, 0.0, double(n - 1));
    l.i0 = std::min(int(c), n - 1);
    l.i1 = std::min(l.i0 + 1, n - 1);
    l.t = c - l.i0;
    return l;
}

Lerp periodic(double x, int n) {
    Lerp l;
    double c = x - 0.5;
    c -= std::floor(c / n) * n;
    l.i0 = std::min(int(c), n - 1);
    l.i1 = (l.i0 + 1) % n;
    l.t = c - l.i0;
    return l;
}

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
    // G: bilinear between cell centres, flat below the first theta centre, and beyond the last
    // one continued along the line through the last two rows towards the horizon (never below
    // 0): the fit's own interpolation (fit/sample_set.h), which lets G fall to 0 at grazing.
    auto gv = [&](const Vec3d& w) {
        const double theta = std::acos(std::clamp(w.z, -1.0, 1.0));
        double phi = std::atan2(w.y, w.x);
        if (phi < 0.0) phi += kTwoPi;
        const Lerp col = periodic(phi / kTwoPi * g_phi, g_phi);
        const double x = std::max(0.0, theta / kHalfPi * g_theta - 0.5);
        const int r0 = std::min(int(x), g_theta - 2);
        const double t = x - r0;  // > 1 beyond the last centre: extrapolation
        auto row = [&](int i) { return double(g[i * g_phi + col.i0]) * (1 - col.t) + double(g[i * g_phi + col.i1]) * col.t; };
        return std::max(0.0, row(r0) * (1 - t) + row(r0 + 1) * t);
    };
    return rho_d[c] + rho_s[c] * dv * fv * gv(wi) * gv(wo) / (wi.z * wo.z);
}

}  // namespace npf
