// relMSE heatmaps, as the paper's insets (Figs. 2, 5, 7): per-pixel relMSE from blue (0) to
// red (5 % and above), pixels not compared black. Colour map and rationale: docs/metrics.md.
#pragma once

#include <npf/render/image_metrics.h>

#include <array>
#include <cstdint>
#include <string>

namespace npf::render {

inline constexpr double kHeatmapMax = 0.05;  // relMSE shown red (and everything above it)

// The colour of `value` on a scale 0 .. `max`: s = value / max clamped to [0, 1], then linearly
// between blue (0, 0, 1) at s = 0, cyan (0, 1, 1) at 1/4, green (0, 1, 0) at 1/2, yellow
// (1, 1, 0) at 3/4 and red (1, 0, 0) at 1; each component rounded to 8 bits. NaN shows red.
// `max` must be finite and > 0 (npf::Error otherwise, from the writer; here it is assumed).
std::array<std::uint8_t, 3> heatmap_colour(double value, double max = kHeatmapMax);

// Writes `map` as an 8-bit RGB PNG at `path`: covered pixels coloured by heatmap_colour,
// the others black. Atomic (a temporary beside `path`, renamed over it when complete).
// Throws npf::Error naming `path` (bad `max`, a map whose sizes disagree, unwritable folder);
// on failure nothing is left at `path` or beside it.
void write_relmse_heatmap(const std::string& path, const RelMseMap& map, double max = kHeatmapMax);

}  // namespace npf::render
