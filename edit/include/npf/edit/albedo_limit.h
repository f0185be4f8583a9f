// Capping the directional albedo: the edit that makes a material that reflects more light than it
// receives (typically a fit at grazing views beyond the measured range) conserve energy, while
// changing nothing where it already does (docs/editing.md, "limit_albedo").
//
// The specular term's albedo at a view w is G(w) times an integral over the light side, so it is
// lowered by scaling G at w's cell: one factor per G cell, shared by all channels (a view keeps
// its colour, the SVD structure of G is kept: every basis value of the cell is scaled). The
// factor is chosen from the albedo at the cell's centre, where G is the cell's value exactly.
// Scaling only ever lowers G, and G also weighs the light side of every other view, so no other
// view's albedo rises: the last pass's exact factors bring every cell centre to the cap at most.
#pragma once

#include <npf/edit/edit_record.h>
#include <npf/shading/npf_albedo.h>
#include <npf/shading/npf_model.h>

#include <functional>

namespace npf::edit {

struct AlbedoLimit {
    double cap = 1.0;  // in (0, 1]
    // Cells are brought to cap (1 - margin), so that the quadrature's own error (below 2e-3
    // relative, docs/editing.md) does not leave them above the cap.
    double margin = 2e-3;
    // Half-vector quadrature per cell centre (as NpfAlbedoQuadrature; 0 chooses). An anisotropic G has
    // g_theta x g_phi centres (16,200 at the paper's size), so 0 there means 64 x 64 cells, for
    // speed: coarser than the check's default (npf_albedo.h), which may read slightly more at
    // grazing views of sharp anisotropic lobes.
    int u_cells = 0, phi_cells = 0;
    // Passes over the G cells (see albedo_limit.cpp): the last one takes the exact factor,
    // the ones before its square root, so that cells lowering each other do not overshoot.
    int passes = 4;  // 1..16
    int threads = 0;                          // 0: all cores
    std::function<void(double)> progress;     // fraction of the cells done, from the calling thread
};

// Throws npf::Error for a cap outside (0, 1], a margin outside [0, 0.1) or passes outside 1..16. Channels whose diffuse
// term alone reaches the cap (pi rho_d >= cap) get rho_d = cap (1 - margin) / pi and rho_s = 0:
// no room is left there for a specular term. D, F, the weights and the other channels' rho_d and
// rho_s are kept; G's basis values of the cells that need no scaling are kept bit for bit. G's
// singular values and kept ratio stay as the provenance of the compression (the scaled bases
// are no longer orthonormal; re-compressing rebuilds both).
NpfModel limit_albedo(const NpfModel& model, const AlbedoLimit& limit, EditRecord* record = nullptr);

}  // namespace npf::edit
