// The directional albedo of an NPF model by a deterministic quadrature on its own tables:
//   a(wi) = integral over the hemisphere of f_r(wi, wo) cos theta_o d(wo).
// This is how npf::directional_albedo (core/directional_albedo.h) answers for a factor texture
// in memory (NpfBrdf), and what edit's albedo cap measures with: one estimator for every report.
//
// The diffuse term gives pi rho_d exactly. The specular term is integrated over the half vector
// (wo = reflect(wi, h), d(wo) = 4 (wi . h) d(h)) on a grid uniform in u = sqrt(theta_h / (pi/2))
// and phi_h, the midpoint rule, evaluating the model exactly as a renderer does (NpfModel, the
// detail layer included); the square-root grid follows the peak of sharp lobes as D's own table
// does, so the cell edges lie on the table's kinks.
#pragma once

#include <npf/core/directional_albedo.h>
#include <npf/core/vec.h>
#include <npf/shading/npf_model.h>

#include <cstddef>
#include <vector>

namespace npf {

struct NpfAlbedoQuadrature {
    // Cells in u and in phi_h; 0 chooses: 4 d_theta cells in u (64 to 256), and 64 in phi_h for
    // an isotropic D, 256 for an anisotropic one. Then within about 2e-3 of a converged integral
    // up to 89 degrees, sharp lobes included (docs/albedo.md: a lobe of alpha 0.02 across a
    // 64-column D, viewed along it at 89 degrees, was 4.6 % low with 64 phi_h cells, 0.7 % high
    // with 128, 0.17 % with 256; at 85 degrees every count was within 0.1 %).
    int u_cells = 0, phi_cells = 0;
};

// a(wi) for every stored channel (model.channel_count() values); all 0 when wi is not above the
// horizon. Bit-identical run to run (sums in double, in a fixed order).
std::vector<double> npf_directional_albedo(const NpfModel& model, const Vec3& wi, const NpfAlbedoQuadrature& cells = {});

// The largest albedo of a model over the views of `views` (by default the one set,
// default_albedo_thetas) and its stored channels: npf convert's energy check and npf edit's
// check after each step. Throws npf::Error when the model is inconsistent (NpfModel::validate).
AlbedoPeak npf_largest_albedo(const NpfModel& model, const AlbedoTableOptions& views = {});

// A model's energy check: what npf convert runs on what it writes (its `albedo_max` metadata)
// and npf edit's albedo cap after its edit:
// the largest directional albedo over the default views (default_albedo_thetas and
// default_albedo_azimuths, those of npf albedo and npf edit's check), by the one estimator
// (directional_albedo.h: for a model, its quadrature, within about 2e-3).
struct EnergyCheck {
    double albedo_max = 0.0, theta_deg = 0.0;
    std::size_t channel = 0;
    // Beyond G's last row centre the model continues G along the line through its last two rows;
    // where that line ends above 0 at the horizon (in any channel with a specular term), the
    // albedo grows like 1 / cos(theta_view) in the last fraction of a degree (docs/editing.md,
    // limit_albedo). Not part of albedo_max: the views above stop at 89 degrees.
    bool unbounded_at_horizon = false;
};
EnergyCheck energy_check(const NpfModel& model, int threads = 0);

}  // namespace npf
