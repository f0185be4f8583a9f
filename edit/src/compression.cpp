#include <npf/edit/compression.h>

#include "tables.h"

#include <algorithm>
#include <string>

namespace npf::edit {

NpfModel compress_model(const NpfModel& model, const CompressionOptions& options, EditRecord* record) {
    const std::size_t C = model.channel_count();
    const detail::Tables d = detail::expand(model.D, C), g = detail::expand(model.G, C);
    NpfFactors f;
    f.grid = RusinkiewiczGrid{model.d_theta, model.d_phi, model.f_theta, 1};
    f.g_theta = model.g_theta;
    f.g_phi = model.g_phi;
    f.channels = model.channels;
    f.rho_d = model.rho_d;
    f.rho_s = model.rho_s;
    f.F = model.F;
    f.D.resize(d.v.size());
    f.G.resize(g.v.size());
    std::transform(d.v.begin(), d.v.end(), f.D.begin(), [](double x) { return float(x); });
    std::transform(g.v.begin(), g.v.end(), f.G.begin(), [](double x) { return float(x); });
    // Ranks above the input's would only add components of zero weight.
    CompressionOptions o = options;
    const bool capped = o.d_rank > model.D.rank || o.g_rank > model.G.rank;
    o.d_rank = std::min(o.d_rank, model.D.rank);
    o.g_rank = std::min(o.g_rank, model.G.rank);
    NpfModel out = compress_factors(f, o);
    out.metadata = model.metadata;
    if (record) {
        record->summary = "re-compressed D rank " + std::to_string(model.D.rank) + " -> " + std::to_string(out.D.rank) +
                          " (kept ratio " + detail::num(out.D.kept_ratio, 6) + "), G rank " +
                          std::to_string(model.G.rank) + " -> " + std::to_string(out.G.rank) + " (kept ratio " +
                          detail::num(out.G.kept_ratio, 6) + ")";
        if (capped) {
            detail::warn(record, "the input was stored at a lower rank: components it dropped cannot come back, "
                                 "its ranks are kept");
        }
    }
    return out;
}

}  // namespace npf::edit
