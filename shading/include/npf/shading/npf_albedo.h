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

}  // namespace npf
