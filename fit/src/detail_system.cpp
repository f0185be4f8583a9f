// The detail fit's problem (detail_system.h): its checks, and its assembly, one step after the
// other (detail_steps.h).
#include "detail_steps.h"

#include <npf/core/error.h>
#include <npf/shading/npf_equation.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace npf::fit_detail {

namespace {

// Channels beyond this many share one data weight (from their mean), and so one matrix: a
// spectral material's neighbouring wavelengths then also warm-start each other's solve.
constexpr std::size_t kMaxWeightGroups = 16;

const char* const kWhat = "detail layer";

}  // namespace

HalfDiff DetailSystem::sample_angles(std::size_t a, int b, int c, int e) const {
    HalfDiff hd;
    hd.theta_h = theta_h.angle[a];
    hd.phi_h = phi_h_samples == 1 ? 0.0 : equation::phi_centre(e, phi_h_samples);
    hd.theta_d = theta_d.angle[std::size_t(b)];
    hd.phi_d = phi_d.angle[std::size_t(c)];
    return hd;
}

double DetailSystem::energy_error(const std::vector<double>& model_albedo) const {
    double worst = 0.0;
    for (std::size_t i = 0; i < albedo_source.size(); ++i) {
        if (albedo_source[i] > 1e-4) worst = std::max(worst, std::abs(model_albedo[i] / albedo_source[i] - 1.0));
    }
    return worst;
}

void check_detail_options(const DetailOptions& o) {
    const DetailGrid& g = o.grid;
    if (g.theta_h < 1 || g.theta_d < 1 || g.phi_d < 1 || g.theta_h > 1024 || g.theta_d > 1024 || g.phi_d > 4096 ||
        g.cells() > NpfModel::kMaxDetailCells) {
        throw Error(kWhat, "grid " + std::to_string(g.theta_h) + "x" + std::to_string(g.theta_d) + "x" +
                               std::to_string(g.phi_d) + " is outside 1..1024 x 1..1024 x 1..4096 (" +
                               std::to_string(NpfModel::kMaxDetailCells) + " cells at most)");
    }
    if (o.samples_per_cell < 1 || o.samples_per_cell > 16) throw Error(kWhat, "samples per cell must be 1..16");
    if (o.phi_h_samples < 1 || o.phi_h_samples > 256) throw Error(kWhat, "phi_h samples must be 1..256");
    if (!(o.display_power >= 0.0 && o.display_power <= 4.0)) throw Error(kWhat, "display power must be 0..4");
    if (!(o.display_epsilon > 0.0)) throw Error(kWhat, "display epsilon must be positive");
    if (!(o.energy_weight >= 0.0) || !std::isfinite(o.energy_weight)) throw Error(kWhat, "energy weight must be >= 0");
    if (!(o.smoothness >= 0.0) || !std::isfinite(o.smoothness)) throw Error(kWhat, "smoothness must be >= 0");
    if (!(o.ratio > 0.0 && o.ratio <= 1.0)) throw Error(kWhat, "ratio must lie in (0, 1]");
    if (o.rank < 0) throw Error(kWhat, "rank must be 0 (by ratio) or positive");
    if (o.clamp_passes < 0 || o.clamp_passes > 16) throw Error(kWhat, "clamp passes must be 0..16");
    for (double v : o.energy_views_deg) {
        if (!(v >= 0.0 && v < 90.0)) throw Error(kWhat, "energy views must lie in [0, 90) degrees");
    }
}

DetailSystem assemble_detail_system(const Brdf& source, const NpfModel& model, const DetailOptions& o, int threads,
                                    const std::function<void(double)>& progress) {
    check_detail_options(o);
    const auto report_progress = [&](double f) {
        if (progress) progress(f);
    };
    const ChannelQuery query = source.query(model.channels);
    DetailSystem sys;
    sys.grid = o.grid;
    sys.channels = model.channel_count();
    sys.cells = o.grid.cells();
    sys.groups = sys.channels <= kMaxWeightGroups ? sys.channels : 1;
    sample_residual(source, query, model, o, threads, sys);
    report_progress(0.3);
    add_data_term(threads, sys);
    report_progress(0.5);
    add_smoothness(o, sys);
    add_energy_rows(source, query, model, o, threads, sys);
    report_progress(0.6);
    weigh_energy_rows(o, sys);
    return sys;
}

}  // namespace npf::fit_detail
