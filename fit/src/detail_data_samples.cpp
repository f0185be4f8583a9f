// The detail fit's data samples (detail_steps.h): a regular lattice, samples_per_cell per cell
// and axis, where the residual of the source against the model and the data weights are taken.
#include "detail_steps.h"

#include <npf/core/parallel.h>
#include <npf/shading/npf_equation.h>

#include <algorithm>
#include <cmath>

namespace npf::fit_detail {

namespace {

// The lattice's axes: u_h-uniform in theta_h, uniform in theta_d and phi_d.
void make_axes(const DetailGrid& g, int k, DetailSystem& sys) {
    const int sh = g.theta_h * k, sd = g.theta_d * k, sp = g.phi_d * k;
    for (int a = 0; a < sh; ++a) {
        const double u = (a + 0.5) / sh;
        sys.theta_h.angle.push_back(equation::theta_h_of_u(u));
        sys.theta_h.measure.push_back(kPiD * u / sh);  // d(theta_h) = pi u du
        sys.theta_h.lerp.push_back(detail_position(g, u, 0.0, 0.0).h);
    }
    for (int b = 0; b < sd; ++b) {
        const double td = equation::theta_centre(b, sd);
        sys.theta_d.angle.push_back(td);
        sys.theta_d.measure.push_back(kHalfPiD / sd);
        sys.theta_d.lerp.push_back(detail_position(g, 0.0, td, 0.0).d);
    }
    for (int c = 0; c < sp; ++c) {
        const double pd = equation::phi_centre(c, sp);
        sys.phi_d.angle.push_back(pd);
        sys.phi_d.measure.push_back(kTwoPiD / sp);
        sys.phi_d.lerp.push_back(detail_position(g, 0.0, 0.0, pd).p);
    }
}

// Per theta_h row of samples: sum w r^2 and sum w f^2 per channel, and the valid samples. Each
// row is summed by one thread, in sample order, then the rows in order: the same on any number
// of threads.
struct RowSums {
    std::vector<double> error, norm;  // [rows][channels]
    std::vector<std::size_t> valid;   // [rows]
};

// Sample s at (a, b, c, e): its residual and weights, its row's sums; what eval_cos reads goes
// through `raw` and `base`, the caller's buffers.
void sample_one(const Brdf& source, const ChannelQuery& query, const NpfModel& model, const DetailOptions& o,
                std::size_t a, int b, int c, int e, DetailSystem& sys, RowSums& rows, std::vector<float>& raw,
                std::vector<double>& base) {
    const std::size_t C = sys.channels, groups = sys.groups;
    const std::size_t s = sys.sample_index(a, b, c, e);
    const HalfDiff hd = sys.sample_angles(a, b, c, e);
    Vec3d wi, wo;
    directions_from_half_diff(hd, wi, wo);
    if (!(wi.z > 1e-6) || !(wo.z > 1e-6)) return;
    const Vec3 fi = to_float(wi), fo = to_float(wo);
    source.eval_cos(fi, fo, query, raw.data());
    model.eval_all(fi, fo, base.data());
    const double along_h = o.measure == DetailOptions::Measure::SolidAngle ? std::sin(hd.theta_h) : 1.0;
    const double measure = 4.0 * along_h * std::sin(hd.theta_d) * std::cos(hd.theta_d) * sys.theta_h.measure[a] *
                           sys.theta_d.measure[std::size_t(b)] * sys.phi_d.measure[std::size_t(c)] *
                           (kTwoPiD / sys.phi_h_samples) * wi.z * wo.z;
    float* residual = &sys.residual[s * C];
    float* weight = &sys.weight[s * groups];
    double mean = 0.0;
    bool finite = true;
    for (std::size_t ch = 0; ch < C; ++ch) {
        const double f = double(raw[ch]) / fo.z;
        finite = finite && std::isfinite(f);
        residual[ch] = float(f - base[ch]);
        mean += std::max(f, 0.0);
    }
    if (!finite) return;
    mean /= double(C);
    for (std::size_t gr = 0; gr < groups; ++gr) {
        const double f = groups == 1 ? mean : std::max(double(raw[gr]) / fo.z, 0.0);
        weight[gr] = float(measure * std::pow(f + o.display_epsilon, -o.display_power));
    }
    ++rows.valid[a];
    for (std::size_t ch = 0; ch < C; ++ch) {
        const double w = weight[sys.group_of(ch)];
        const double f = double(raw[ch]) / fo.z;
        rows.error[a * C + ch] += w * double(residual[ch]) * residual[ch];
        rows.norm[a * C + ch] += w * f * f;
    }
}

}  // namespace

void sample_residual(const Brdf& source, const ChannelQuery& query, const NpfModel& model, const DetailOptions& o,
                     int threads, DetailSystem& sys) {
    const std::size_t C = sys.channels;
    make_axes(sys.grid, o.samples_per_cell, sys);
    sys.phi_h_samples = model.isotropic() ? 1 : o.phi_h_samples;
    const std::size_t sh = sys.theta_h.angle.size();
    const std::size_t samples = sh * sys.theta_d.angle.size() * sys.phi_d.angle.size() * std::size_t(sys.phi_h_samples);
    sys.residual.assign(samples * C, 0.f);
    sys.weight.assign(samples * sys.groups, 0.f);
    RowSums rows{std::vector<double>(sh * C, 0.0), std::vector<double>(sh * C, 0.0), std::vector<std::size_t>(sh, 0)};
    npf::parallel_slices(sh, std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
        std::vector<float> raw(C);
        std::vector<double> base(C);
        for (std::size_t a = begin; a < end; ++a) {
            for_each_sample_of_row(sys, [&](int b, int c, int e) { sample_one(source, query, model, o, a, b, c, e, sys, rows, raw, base); });
        }
    }, threads);
    sys.data_error.assign(C, 0.0);
    sys.data_norm.assign(C, 0.0);
    for (std::size_t a = 0; a < sh; ++a) {
        sys.samples_valid += rows.valid[a];
        for (std::size_t ch = 0; ch < C; ++ch) {
            sys.data_error[ch] += rows.error[a * C + ch];
            sys.data_norm[ch] += rows.norm[a * C + ch];
        }
    }
}

}  // namespace npf::fit_detail
