// The steps that assemble and solve the detail fit's problem (detail_system.h), one file each:
// assemble_detail_system (detail_system.cpp) runs the assembly steps in this order, and
// fit_detail_layer (detail_fit.cpp) the solve. Internal to the fitter: not installed.
#pragma once

#include "detail_system.h"

#include <npf/core/brdf.h>
#include <npf/core/vec.h>

#include <vector>

namespace npf::fit_detail {

inline Vec3 to_float(const Vec3d& v) { return Vec3(float(v.x), float(v.y), float(v.z)); }

// fn(b, c, e) for the samples (a, b, c, e) of theta_h row a, in storage order.
template <class Fn>
void for_each_sample_of_row(const DetailSystem& system, Fn&& fn) {
    const int sd = int(system.theta_d.angle.size()), sp = int(system.phi_d.angle.size()), se = system.phi_h_samples;
    for (int b = 0; b < sd; ++b) {
        for (int c = 0; c < sp; ++c) {
            for (int e = 0; e < se; ++e) fn(b, c, e);
        }
    }
}

// detail_data_samples.cpp: the sample axes, and at every sample the residual f_source - f_model
// and the data weights; data_error, data_norm and samples_valid.
void sample_residual(const Brdf& source, const ChannelQuery& query, const NpfModel& model, const DetailOptions& options,
                     int threads, DetailSystem& system);

// detail_data_term.cpp: the data term's normal equations (the stencils and the right-hand sides),
// then the neighbour table and the smoothness term folded into the stencils.
void add_data_term(int threads, DetailSystem& system);
void add_smoothness(const DetailOptions& options, DetailSystem& system);

// detail_energy_rows.cpp: the energy rows (the directional albedo at each view, linear in the
// grid values) with the source's and the model's albedo, then each channel's row weights and
// the rows' targets added to the right-hand sides.
void add_energy_rows(const Brdf& source, const ChannelQuery& query, const NpfModel& model, const DetailOptions& options,
                     int threads, DetailSystem& system);
void weigh_energy_rows(const DetailOptions& options, DetailSystem& system);
// The albedo of `model` as it evaluates, its clamp max(0, NPF + r) included, at each of the
// system's views by the energy rows' quadrature: [views][channels].
std::vector<double> clamped_albedo(const DetailSystem& system, const NpfModel& model, int threads);

}  // namespace npf::fit_detail
