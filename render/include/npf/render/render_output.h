// Writing a render: a float RGBA OpenEXR file with what the values are and how they were made
// in its header, published by npf::AtomicOutput (never a half-written file; docs/reliability.md).
#pragma once

#include <npf/core/atomic_file.h>
#include <npf/render/lighting.h>
#include <npf/render/path_tracer.h>

#include <string>
#include <utility>
#include <vector>

namespace npf::render {

// Header attributes, in order: ("npf:material", path), ("npf:spp", "64"), ... Names without a
// namespace prefix get "npf:".
using RenderMetadata = std::vector<std::pair<std::string, std::string>>;

// The attributes every render file carries: npf:values (what the pixels are), npf:scene,
// npf:size, npf:spp, npf:seed, npf:channels ("rgb" or the wavelengths in nm), npf:sampling,
// npf:threads, npf:render_seconds, npf:envmap (environment.source()), npf:envmap_size,
// npf:envmap_clamped_values, and npf:dropped_values when some were dropped.
// Callers add the material and anything else.
RenderMetadata describe_render(const RenderResult& result, const RenderOptions& options,
                               const EnvironmentMap& environment);
// The same under any lighting, with npf:lighting (its label): a map's lines as above; directional
// lights' npf:lights (each light's direction and irradiance) and npf:sampling saying that there
// was no Monte Carlo (npf:spp 1: one ray through each pixel's centre).
RenderMetadata describe_render(const RenderResult& result, const RenderOptions& options, const Lighting& lighting);

// Writes result.image (premultiplied linear Rec.709 RGBA, 32-bit float, ZIP compression, the
// Rec.709 chromaticities, DateTime) with `metadata` as string attributes. Throws npf::Error
// naming `path`; on failure the earlier file at `path` is untouched and nothing is left beside it.
void write_render_exr(const std::string& path, const RenderResult& result, const RenderMetadata& metadata);

// The same into `out`, not committed: for publishing with another output (npf::commit_together).
void write_render_exr(AtomicOutput& out, const RenderResult& result, const RenderMetadata& metadata);

}  // namespace npf::render
