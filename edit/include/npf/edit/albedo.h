// Physical sanity of an edited material: its directional albedo
//   a(wi) = integral over the hemisphere of f_r(wi, wo) cos theta_o d(wo),
// the share of light from wi that is reflected, must not exceed 1.
//
// The diffuse term gives pi rho_d exactly. The specular term is integrated over the half vector
// (wo = reflect(wi, h), d(wo) = 4 (wi . h) d(h)) on a grid uniform in u = sqrt(theta_h / (pi/2))
// and phi_h, the midpoint rule, evaluating the model exactly as a renderer does (NpfModel); the
// square-root grid follows the peak of sharp lobes as D's own table does.
#pragma once

#include <npf/core/vec.h>
#include <npf/shading/npf_model.h>

#include <cstddef>
#include <vector>

namespace npf::edit {

struct AlbedoOptions {
    // Incident directions: these polar angles (degrees) at `azimuths` evenly spaced azimuths
    // (one, phi = 0, for an isotropic model).
    std::vector<double> theta_deg = {0, 30, 50, 65, 75, 85};
    int azimuths = 8;
    // Half-vector grid: cells in u and in phi_h; 0 chooses from D's grid: 4 d_theta cells in u
    // (at least 64, at most 256: the midpoint rule then has its cell edges on the table's kinks
    // and is within about 2e-3 of a converged integral even for lobes the table barely
    // resolves), 64 in phi_h for an isotropic D, else d_phi (at least 64, at most 128).
    int u_cells = 0, phi_cells = 0;
    int threads = 0;  // directions are shared out over this many threads; 0: all cores
};

// a(wi) for every stored channel. wi must point above the horizon.
std::vector<double> directional_albedo(const NpfModel& model, const Vec3& wi, const AlbedoOptions& options = {});

struct AlbedoReport {
    double max = 0.0;                       // the largest albedo over directions and channels
    double theta_deg = 0.0, phi_deg = 0.0;  // where it occurs
    std::size_t channel = 0;
};

AlbedoReport albedo_report(const NpfModel& model, const AlbedoOptions& options = {});

}  // namespace npf::edit
