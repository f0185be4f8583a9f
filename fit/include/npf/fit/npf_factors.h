// The non-parametric factors of a material (paper Eq. 1), per channel (RGB or wavelength):
//   rho(wi, wo) = rho_d + rho_s D(theta_h, phi_h) F(theta_d) G(theta_i, phi_i) G(theta_o, phi_o)
//                 / (cos theta_i cos theta_o)
// on the tables of a RusinkiewiczGrid: D over (sqrt-mapped theta_h, phi_h) cell centres, F over
// theta_d cell centres, G over (theta, phi) cell centres uniform in theta. Isotropic factors
// have one phi_h and one G phi cell.
//
// Gauge (the model is invariant under rescalings between rho_s, D, F, G; these fix it):
// integral D(h) cos(theta_h) dh = 1 (projected area), G at normal incidence = 1, and F at normal
// incidence (theta_d = 0) = 1, so that rho_s is the specular colour at normal incidence.
#pragma once

#include <npf/fit/rusinkiewicz.h>
#include <npf/core/channels.h>

#include <cstddef>
#include <vector>

namespace npf {

struct NpfFactors {
    RusinkiewiczGrid grid;       // D uses theta_h x phi_h, F uses theta_d
    int g_theta = 90, g_phi = 180;  // G's table; g_phi = 1 when isotropic
    Channels channels;
    std::vector<float> rho_d, rho_s;  // [C]
    std::vector<float> D;             // [C][theta_h][phi_h]
    std::vector<float> F;             // [C][theta_d]
    std::vector<float> G;             // [C][g_theta][g_phi]

    std::size_t channel_count() const { return rho_d.size(); }
    std::size_t d_size() const { return std::size_t(grid.theta_h) * std::size_t(grid.phi_h); }
    std::size_t g_size() const { return std::size_t(g_theta) * std::size_t(g_phi); }

    // rho(wi, wo) of channel c by bilinear interpolation of the tables on their cell centres
    // (periodic in phi, clamped in theta, except G beyond its last theta centre, which follows
    // the line through its last two rows to the horizon, never below 0); 0 when a direction
    // is at or below the horizon.
    double eval(std::size_t c, const Vec3d& wi, const Vec3d& wo) const;
};

}  // namespace npf
