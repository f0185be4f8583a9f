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
    const HalfVectorGrid grid(nu, np);
    const double du = grid.du(), dphi = grid.dphi();
    std::vector<double> spec(C, 0.0), values(C);
    NpfModel::Lookup at;
    grid.for_each_node(wi.x, wi.y, wi.z, 1e-7, [&](const HalfVectorNode& n) {
        const Vec3 wo{float(n.ox), float(n.oy), float(n.oz)};
        if (!model.prepare(wi, normalize(wo), at)) return;
        const double solid = n.sin_theta_h * kPiD * n.u * du * dphi;  // d(theta_h) = pi u du
        const double weight = n.oz * 4.0 * n.cos_ih * solid;
        model.values(at, values.data());
        for (std::size_t c = 0; c < C; ++c) spec[c] += (values[c] - model.rho_d[c]) * weight;
    });
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
