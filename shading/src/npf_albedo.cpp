#include <npf/shading/npf_albedo.h>

#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_equation.h>

#include <algorithm>
#include <cmath>

namespace npf {

std::vector<double> npf_directional_albedo(const NpfModel& model, const Vec3& wi, const NpfAlbedoQuadrature& cells) {
    const std::size_t C = model.channel_count();
    std::vector<double> a(C, 0.0);
    if (!(wi.z > 0.f)) return a;
    const int nu = cells.u_cells > 0 ? cells.u_cells : std::clamp(4 * model.d_theta, 64, 256);
    const int np = cells.phi_cells > 0 ? cells.phi_cells : (model.d_phi == 1 ? 64 : 256);
    const double du = 1.0 / nu, dphi = 2.0 * kPiD / np;
    const double ix = wi.x, iy = wi.y, iz = wi.z;
    std::vector<double> spec(C, 0.0);
    // The azimuths' sines and cosines once, not once per ring (they were a tenth of the time).
    std::vector<double> cos_phi(np), sin_phi(np);
    for (int j = 0; j < np; ++j) {
        const double phi = (j + 0.5) * dphi;
        cos_phi[j] = std::cos(phi);
        sin_phi[j] = std::sin(phi);
    }
    std::vector<double> values(C);
    NpfModel::Lookup at;
    for (int i = 0; i < nu; ++i) {
        const double u = (i + 0.5) * du, theta = equation::theta_h_of_u(u), st = std::sin(theta), ct = std::cos(theta);
        const double solid = st * kPiD * u * du * dphi;  // d(theta_h) = pi u du
        for (int j = 0; j < np; ++j) {
            const double hx = st * cos_phi[j], hy = st * sin_phi[j], hz = ct;
            const double d = ix * hx + iy * hy + iz * hz;
            if (!(d > 0.0)) continue;
            const double ox = 2.0 * d * hx - ix, oy = 2.0 * d * hy - iy, oz = 2.0 * d * hz - iz;
            if (!(oz > 1e-7)) continue;
            const Vec3 wo{float(ox), float(oy), float(oz)};
            if (!model.prepare(wi, normalize(wo), at)) continue;
            const double weight = oz * 4.0 * d * solid;
            model.values(at, values.data());
            for (std::size_t c = 0; c < C; ++c) spec[c] += (values[c] - model.rho_d[c]) * weight;
        }
    }
    for (std::size_t c = 0; c < C; ++c) a[c] = kPiD * model.rho_d[c] + spec[c];
    return a;
}

AlbedoPeak npf_largest_albedo(const NpfModel& model, const AlbedoTableOptions& views) {
    const NpfBrdf brdf(model);
    return largest_albedo(directional_albedo_table(brdf, brdf.native_query(), views));
}

EnergyCheck energy_check(const NpfModel& model, int threads) {
    EnergyCheck e;
    AlbedoTableOptions views;
    views.threads = threads;
    const AlbedoPeak peak = npf_largest_albedo(model, views);
    e.albedo_max = peak.max;
    e.theta_deg = peak.theta_deg;
    e.channel = peak.channel;
    e.unbounded_at_horizon = model.g_open_at_horizon();
    return e;
}

}  // namespace npf
