#include <npf/edit/compression.h>

#include "tables.h"

#include <npf/core/number_text.h>

#include <algorithm>
#include <string>

namespace npf::edit {

NpfModel compress_model(const NpfModel& model, const CompressionOptions& options, EditRecord* record) {
    const std::size_t C = model.channel_count();
    const detail::Tables d = detail::expand(model.D, C), g = detail::expand(model.G, C);
    const NpfFactors f = detail::factors_of(model, d, model.d_phi, g, model.g_phi);
    // Ranks above the input's would only add components of zero weight.
    CompressionOptions o = options;
    const bool capped = o.d_rank > model.D.rank || o.g_rank > model.G.rank;
    o.d_rank = std::min(o.d_rank, model.D.rank);
    o.g_rank = std::min(o.g_rank, model.G.rank);
    NpfModel out = compress_factors(f, o);
    out.metadata = model.metadata;
    // Re-compressing D and G leaves the residual's meaning as it was: it is kept as it is.
    out.detail_grid = model.detail_grid;
    out.detail = model.detail;
    if (record) {
        record->summary = "re-compressed D rank " + std::to_string(model.D.rank) + " -> " + std::to_string(out.D.rank) +
                          " (kept ratio " + number_text(out.D.kept_ratio, 6) + "), G rank " +
                          std::to_string(model.G.rank) + " -> " + std::to_string(out.G.rank) + " (kept ratio " +
                          number_text(out.G.kept_ratio, 6) + ")";
        if (capped) {
            detail::warn(record, "the input was stored at a lower rank: components it dropped cannot come back, "
                                 "its ranks are kept");
        }
    }
    return out;
}

}  // namespace npf::edit
