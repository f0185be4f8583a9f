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
#include <npf/shading/npf_equation.h>
#include <npf/shading/npf_model.h>

#include <cmath>
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

// One node of the half-vector quadrature at a view wi (HalfVectorGrid::for_each_node).
struct HalfVectorNode {
    double u, sin_theta_h;  // its ring: theta_h = theta_h_of_u(u), d(theta_h) = pi u du
    double cos_ih;          // wi . h, > 0
    double ox, oy, oz;      // wo = reflect(wi, h), in double
};

// The quadrature's nodes: the midpoint rule on u_cells x phi_cells cells in u and phi_h. Shared
// by npf_directional_albedo and the detail fit's energy rows (fit/src/detail_energy_rows.cpp),
// which integrate the same way over the half vector; each forms its own weight from the node
// (their products are ordered differently, and both are kept to the bit). Inline, so that every
// caller computes the nodes under its own compile flags, as it did before they were shared.
class HalfVectorGrid {
public:
    HalfVectorGrid(int u_cells, int phi_cells)
        : m_u_cells(u_cells), m_phi_cells(phi_cells), m_du(1.0 / u_cells), m_dphi(2.0 * kPiD / phi_cells),
          m_cos_phi(std::size_t(phi_cells)), m_sin_phi(std::size_t(phi_cells)) {
        // The azimuths' sines and cosines once, not once per ring (they were a tenth of the time).
        for (int j = 0; j < phi_cells; ++j) {
            const double phi = (j + 0.5) * m_dphi;
            m_cos_phi[std::size_t(j)] = std::cos(phi);
            m_sin_phi[std::size_t(j)] = std::sin(phi);
        }
    }
    double du() const { return m_du; }
    double dphi() const { return m_dphi; }

    // fn(const HalfVectorNode&) for each half vector h of the grid with wi . h > 0 whose mirror
    // direction wo = reflect(wi, h) lies above min_cos_o, ring by ring, in a fixed order.
    template <class Fn>
    void for_each_node(double ix, double iy, double iz, double min_cos_o, Fn&& fn) const {
        HalfVectorNode n;
        for (int i = 0; i < m_u_cells; ++i) {
            n.u = (i + 0.5) * m_du;
            const double theta = equation::theta_h_of_u(n.u), ct = std::cos(theta);
            n.sin_theta_h = std::sin(theta);
            for (int j = 0; j < m_phi_cells; ++j) {
                const double hx = n.sin_theta_h * m_cos_phi[std::size_t(j)], hy = n.sin_theta_h * m_sin_phi[std::size_t(j)],
                             hz = ct;
                n.cos_ih = ix * hx + iy * hy + iz * hz;
                if (!(n.cos_ih > 0.0)) continue;
                n.ox = 2.0 * n.cos_ih * hx - ix, n.oy = 2.0 * n.cos_ih * hy - iy, n.oz = 2.0 * n.cos_ih * hz - iz;
                if (!(n.oz > min_cos_o)) continue;
                fn(static_cast<const HalfVectorNode&>(n));
            }
        }
    }

private:
    int m_u_cells, m_phi_cells;
    double m_du, m_dphi;
    std::vector<double> m_cos_phi, m_sin_phi;
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
