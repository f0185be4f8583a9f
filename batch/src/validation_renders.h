// A material's validation renders (private to npf_batch; docs/batch.md "Validation renders"):
// the source and its output rendered as a pair under each lighting (render/paired_render.h),
// written to renders/NAME.LIGHTING.reference.exr and .npf.exr beside the output, stamped with
// their render hash.
#pragma once

#include "material_context.h"

#include <npf/batch/config.h>
#include <npf/batch/summary.h>
#include <npf/core/brdf.h>

#include <optional>
#include <string>
#include <vector>

namespace npf::batch::detail {

// renders/NAME.LIGHTING.KIND.exr beside the output; KIND "reference" or "npf".
std::string render_file(const MaterialJob& job, const std::string& lighting, const char* kind);

// The figures of the material's validation renders when every lighting's pair is there and
// stamped with `render_hash`; nothing when any is missing or older.
std::optional<std::vector<LightingCheck>> renders_up_to_date(const MaterialJob& job, const RenderCheck& check,
                                                             const std::string& render_hash);

// Renders the source and its output (`output`, where it can be read now) under each lighting of
// `check`; publishes each lighting's pair, stamped with `render_hash`, and fills the result's
// figures (the worst lighting's).
void render_and_compare(const MaterialJob& job, const Brdf& source, const std::string& output, const RenderCheck& check,
                        const std::string& render_hash, MaterialContext& ctx, MaterialResult& r);

}  // namespace npf::batch::detail
