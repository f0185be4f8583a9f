// The detail fit's weighted least-squares problem, assembled but not yet solved (detail_fit.cpp,
// docs/fitting.md "Detail layer"): the data samples and their weights, the normal equations of
// a trilinear grid's values (the data term's 27-point stencil with the smoothness term folded
// in, the right-hand sides) and the energy rows. fit_detail_layer solves it per channel for the
// shipped grid. Internal to the fitter: not installed.
#pragma once

#include <npf/fit/detail_fit.h>
#include <npf/fit/rusinkiewicz.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace npf::fit_detail {

constexpr int kDetailStencil = 27;  // the 3 x 3 x 3 neighbourhood of a cell
// Slot of corner b relative to corner a in a's 27-point stencil.
inline int stencil_slot(int dh, int dd, int dp) { return (dh + 1) * 9 + (dd + 1) * 3 + (dp + 1); }

// The samples along one axis: their angle, their interpolation on the detail grid and the
// axis' share of the cell measure.
struct DetailAxis {
    std::vector<double> angle, measure;
    std::vector<table::Lerp> lerp;
};

// For channel c, with x the grid values (cells of `grid`), the fit minimises
//   x^T A_c x - 2 rhs[c]^T x,   A_c = stencil[group_of(c)] + sum_v row_weight[c][v] rows[v] rows[v]^T
// (NormalOperator below applies A_c): the weighted data misfit with the smoothness term, and the
// energy term, up to constants.
struct DetailSystem {
    DetailGrid grid;
    std::size_t channels = 0, cells = 0;
    std::size_t groups = 0;  // data weights: one per channel, or one shared (their mean) past 16 channels
    std::size_t group_of(std::size_t c) const { return groups == 1 ? 0 : c; }

    // ---- The data samples: a regular lattice, samples_per_cell per cell and axis ------------
    DetailAxis theta_h, theta_d, phi_d;  // u_h-uniform, uniform, uniform
    int phi_h_samples = 1;               // 1 for isotropic models
    std::size_t sample_index(std::size_t a, int b, int c, int e) const {
        return ((a * theta_d.angle.size() + std::size_t(b)) * phi_d.angle.size() + std::size_t(c)) *
                   std::size_t(phi_h_samples) +
               std::size_t(e);
    }
    HalfDiff sample_angles(std::size_t a, int b, int c, int e) const;
    std::vector<float> residual;  // [samples][channels]: f_source - f_model
    std::vector<float> weight;    // [samples][groups]: the data weight, 0 where the pair is not valid
    std::size_t samples_valid = 0;
    // Per channel: sum w (f_source - f_model)^2 and sum w f_source^2 over the samples.
    std::vector<double> data_error, data_norm;

    // ---- Normal equations ---------------------------------------------------------------------
    std::vector<std::vector<double>> stencil;  // [groups][cells][27], smoothness included
    std::vector<std::int32_t> neighbour;       // [cells][27], -1 outside the grid
    std::vector<std::vector<double>> rhs;      // [channels][cells], the energy targets included

    // ---- Energy term: the directional albedo at each view is rows[v] . x plus the model's ----
    std::vector<std::vector<double>> rows;        // [views][cells]
    std::vector<std::vector<double>> row_weight;  // [channels][views]
    std::vector<double> albedo_source, albedo_base;  // [views][channels], by the fit's quadrature
    std::vector<Vec3d> view_wi;                      // [views]: the view directions
    std::size_t views() const { return rows.size(); }
    // The largest relative albedo error of `model_albedo` ([views][channels]) against the source.
    double energy_error(const std::vector<double>& model_albedo) const;
};

// Throws npf::Error for options out of range (fit_detail_layer's checks).
void check_detail_options(const DetailOptions& options);

// Assembles the problem for options.grid (checked by check_detail_options), the residual of
// `source` (queried at model.channels) against `model` as it evaluates: pass the base model,
// without a detail layer. `progress` gets 0.3, 0.5 and 0.6 (fit_detail_layer's scale).
DetailSystem assemble_detail_system(const Brdf& source, const NpfModel& model, const DetailOptions& options,
                                    int threads, const std::function<void(double)>& progress = {});

// The symmetric operator A_c, applied without forming it.
struct NormalOperator {
    const std::vector<double>* stencil = nullptr;            // [cells][27]
    const std::vector<std::int32_t>* neighbour = nullptr;    // [cells][27], -1 outside the grid
    const std::vector<std::vector<double>>* rows = nullptr;  // energy rows a_v
    std::vector<double> row_weight;                          // per energy row, for this channel
    std::size_t cells = 0;

    // A_c of channel c of `system`.
    static NormalOperator of(const DetailSystem& system, std::size_t channel);
    void apply(const std::vector<double>& x, std::vector<double>& y) const;
    double diagonal(std::size_t i) const;
};

// Jacobi-preconditioned conjugate gradients from the starting point in x; the iterations used.
int solve(const NormalOperator& op, const std::vector<double>& b, std::vector<double>& x, int max_iterations,
          double tolerance);

}  // namespace npf::fit_detail
