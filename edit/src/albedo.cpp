#include <npf/edit/albedo.h>

#include <npf/core/error.h>
#include <npf/core/parallel.h>
#include <npf/shading/npf_equation.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace npf::edit {

std::vector<double> directional_albedo(const NpfModel& model, const Vec3& wi, const AlbedoOptions& options) {
    const std::size_t C = model.channel_count();
    std::vector<double> a(C, 0.0);
    if (!(wi.z > 0.f)) return a;
    const int nu = options.u_cells > 0 ? options.u_cells : std::clamp(4 * model.d_theta, 64, 256);
    const int np = options.phi_cells > 0 ? options.phi_cells : (model.d_phi == 1 ? 64 : std::clamp(model.d_phi, 64, 128));
    const double du = 1.0 / nu, dphi = 2.0 * kPiD / np;
    const double ix = wi.x, iy = wi.y, iz = wi.z;
    std::vector<double> spec(C, 0.0), values(C);
    NpfModel::Lookup at;
    for (int i = 0; i < nu; ++i) {
        const double u = (i + 0.5) * du, theta = equation::theta_h_of_u(u), st = std::sin(theta), ct = std::cos(theta);
        const double solid = st * kPiD * u * du * dphi;  // d(theta_h) = pi u du
        for (int j = 0; j < np; ++j) {
            const double phi = (j + 0.5) * dphi;
            const double hx = st * std::cos(phi), hy = st * std::sin(phi), hz = ct;
            const double d = ix * hx + iy * hy + iz * hz;
            if (!(d > 0.0)) continue;
            const double ox = 2.0 * d * hx - ix, oy = 2.0 * d * hy - iy, oz = 2.0 * d * hz - iz;
            if (!(oz > 1e-7)) continue;
            const Vec3 wo{float(ox), float(oy), float(oz)};
            if (!model.prepare(wi, normalize(wo), at)) continue;
            const double weight = oz * 4.0 * d * solid;
            for (std::size_t c = 0; c < C; ++c) spec[c] += (model.value(at, c) - model.rho_d[c]) * weight;
        }
    }
    for (std::size_t c = 0; c < C; ++c) a[c] = kPiD * model.rho_d[c] + spec[c];
    return a;
}

AlbedoReport albedo_report(const NpfModel& model, const AlbedoOptions& options) {
    const int azimuths = model.isotropic() ? 1 : std::max(1, options.azimuths);
    std::vector<Vec3> dirs;
    std::vector<std::pair<double, double>> angles;
    for (double t : options.theta_deg) {
        if (!(t >= 0.0 && t < 90.0)) throw Error("albedo check", "incident angle " + std::to_string(t) + " is not in [0, 90)");
        for (int k = 0; k < azimuths; ++k) {
            const double p = 360.0 * k / azimuths;
            dirs.push_back(spherical_direction(float(t * kPiD / 180.0), float(p * kPiD / 180.0)));
            angles.emplace_back(t, p);
        }
    }
    std::vector<std::vector<double>> albedo(dirs.size());
    parallel_for(dirs.size(), [&](std::size_t i) { albedo[i] = directional_albedo(model, dirs[i], options); }, options.threads);
    AlbedoReport r;
    bool first = true;
    for (std::size_t i = 0; i < dirs.size(); ++i) {
        for (std::size_t c = 0; c < albedo[i].size(); ++c) {
            if (first || albedo[i][c] > r.max) {
                r.max = albedo[i][c];
                r.theta_deg = angles[i].first;
                r.phi_deg = angles[i].second;
                r.channel = c;
                first = false;
            }
        }
    }
    return r;
}

}  // namespace npf::edit
