// The detail fit's energy term (detail_steps.h): the directional albedo at each view, by a
// half-vector quadrature, is linear in the grid values; its rows hold it to the source's.
#include "detail_steps.h"

#include <npf/core/parallel.h>
#include <npf/shading/npf_albedo.h>
#include <npf/shading/npf_equation.h>

#include <algorithm>
#include <cmath>

namespace npf::fit_detail {

namespace {

// The fit's albedo quadrature at view wi: fn(wo, q) for each wo = reflect(wi, h), h on a
// square-root grid in theta_h (dense at the peak), q = 4 (wi . h) d(omega_h) cos(theta_o), so
// that albedo(wi) = sum q f_r(wi, wo). The nodes are npf_directional_albedo's (npf_albedo.h),
// on a fixed 128 x 128 grid: the fit integrates the source, which has no table to size the grid
// by and no diffuse term to take out exactly. The weight's product is ordered as it was when the
// fit had its own nodes (npf_directional_albedo orders its own differently): the bits of every
// fitted layer stay as they were.
template <class Fn>
void for_each_albedo_sample(const Vec3d& wi, Fn&& fn) {
    constexpr int kU = 128, kPhi = 128;
    static const HalfVectorGrid grid(kU, kPhi);
    if (!(wi.z > 1e-6)) return;
    grid.for_each_node(wi.x, wi.y, wi.z, 1e-6, [&](const HalfVectorNode& n) {
        const double dtheta = kPiD * n.u / kU;
        fn(Vec3d{n.ox, n.oy, n.oz}, 4.0 * n.cos_ih * n.sin_theta_h * dtheta * (kTwoPiD / kPhi) * n.oz);
    });
}

// The views: each of options.energy_views_deg, at one azimuth (isotropic) or four.
std::vector<Vec3d> view_directions(const NpfModel& model, const DetailOptions& o) {
    std::vector<Vec3d> views;
    if (!(o.energy_weight > 0.0)) return views;
    const std::vector<double> azimuths = model.isotropic() ? std::vector<double>{0.0}
                                                           : std::vector<double>{0.0, 0.25 * kPiD, 0.5 * kPiD, 0.75 * kPiD};
    for (double v : o.energy_views_deg) {
        for (double phi : azimuths) {
            const double theta = v * kPiD / 180.0, st = std::sin(theta), ct = std::cos(theta);
            views.push_back(Vec3d{st * std::cos(phi), st * std::sin(phi), ct});
        }
    }
    return views;
}

}  // namespace

// albedo(wi) = integral f(wi, wo) cos(theta_o) d(omega_o), wo = reflect(wi, h),
// d(omega_o) = 4 (wi . h) d(omega_h), h on a square-root grid in theta_h (dense at the peak).
void add_energy_rows(const Brdf& source, const ChannelQuery& query, const NpfModel& model, const DetailOptions& o,
                     int threads, DetailSystem& sys) {
    const std::size_t C = sys.channels;
    sys.view_wi = view_directions(model, o);
    const std::size_t V = sys.view_wi.size();
    sys.rows.assign(V, std::vector<double>(sys.cells, 0.0));
    sys.albedo_source.assign(V * C, 0.0);
    sys.albedo_base.assign(V * C, 0.0);
    npf::parallel_slices(V, std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
        std::vector<float> raw(C);
        std::vector<double> base(C);
        for (std::size_t v = begin; v < end; ++v) {
            const Vec3d wi = sys.view_wi[v];
            double* source_albedo = &sys.albedo_source[v * C];
            double* base_albedo = &sys.albedo_base[v * C];
            std::vector<double>& row = sys.rows[v];
            for_each_albedo_sample(wi, [&](const Vec3d& wo, double q) {
                const Vec3 fi = to_float(wi), fo = to_float(wo);
                source.eval_cos(fi, fo, query, raw.data());
                model.eval_all(fi, fo, base.data());
                bool finite = true;
                for (std::size_t ch = 0; ch < C; ++ch) finite = finite && std::isfinite(raw[ch]);
                if (!finite) return;
                for (std::size_t ch = 0; ch < C; ++ch) {
                    source_albedo[ch] += q * std::max(0.0, double(raw[ch]) / fo.z);
                    base_albedo[ch] += q * base[ch];
                }
                const HalfDiff hd = half_diff_from_directions(wi, wo);
                const DetailPosition at = detail_position(sys.grid, equation::u_of_theta_h(hd.theta_h), hd.theta_d, hd.phi_d);
                const Trilinear t = trilinear(sys.grid, at);
                for (int j = 0; j < 8; ++j) row[t.index[j]] += q * t.weight[j];
            });
        }
    }, threads);
}

void weigh_energy_rows(const DetailOptions& o, DetailSystem& sys) {
    const std::size_t C = sys.channels, V = sys.views();
    sys.row_weight.assign(C, std::vector<double>(V, 0.0));
    for (std::size_t ch = 0; ch < C; ++ch) {
        if (!(V > 0 && sys.data_error[ch] > 0.0)) continue;
        std::vector<double>& row_weight = sys.row_weight[ch];
        std::vector<double>& b = sys.rhs[ch];
        // A 1 % albedo error at every view costs energy_weight 1e-4 times the base's misfit.
        const double lambda = o.energy_weight * sys.data_error[ch] / double(V);
        double largest = 0.0;
        for (std::size_t v = 0; v < V; ++v) largest = std::max(largest, sys.albedo_source[v * C + ch]);
        for (std::size_t v = 0; v < V; ++v) {
            const double scale = std::max(sys.albedo_source[v * C + ch], 1e-3 * largest);
            if (!(scale > 0.0)) continue;
            row_weight[v] = lambda / (scale * scale);
            const double target = sys.albedo_source[v * C + ch] - sys.albedo_base[v * C + ch];
            for (std::size_t i = 0; i < sys.cells; ++i) b[i] += row_weight[v] * sys.rows[v][i] * target;
        }
    }
}

std::vector<double> clamped_albedo(const DetailSystem& sys, const NpfModel& model, int threads) {
    const std::size_t C = sys.channels, V = sys.views();
    std::vector<double> albedo(V * C, 0.0);
    npf::parallel_slices(V, std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
        std::vector<double> with(C);
        for (std::size_t v = begin; v < end; ++v) {
            const Vec3 fi = to_float(sys.view_wi[v]);
            for_each_albedo_sample(sys.view_wi[v], [&](const Vec3d& wo, double q) {
                NpfModel::Lookup at;
                if (!model.prepare(fi, to_float(wo), at)) return;
                model.values(at, with.data());
                for (std::size_t ch = 0; ch < C; ++ch) albedo[v * C + ch] += q * with[ch];
            });
        }
    }, threads);
    return albedo;
}

}  // namespace npf::fit_detail
