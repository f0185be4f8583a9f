// relMSE heatmaps: a blue-cyan-green-yellow-red ramp, written as 8-bit PNG (docs/metrics.md).
#include <npf/render/heatmap.h>

#include <npf/color/display_image.h>
#include <npf/core/error.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace npf::render {

namespace {

std::uint8_t to_8bit(double v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); }

}  // namespace

std::array<std::uint8_t, 3> heatmap_colour(double value, double max) {
    const double s = std::isnan(value) ? 1.0 : std::clamp(value / max, 0.0, 1.0);
    double r = 0.0, g = 0.0, b = 0.0;
    if (s < 0.25) {  // blue -> cyan
        g = 4.0 * s, b = 1.0;
    } else if (s < 0.5) {  // cyan -> green
        g = 1.0, b = 1.0 - 4.0 * (s - 0.25);
    } else if (s < 0.75) {  // green -> yellow
        r = 4.0 * (s - 0.5), g = 1.0;
    } else {  // yellow -> red
        r = 1.0, g = 1.0 - 4.0 * (s - 0.75);
    }
    return {to_8bit(r), to_8bit(g), to_8bit(b)};
}

void write_relmse_heatmap(const std::string& path, const RelMseMap& map, double max) {
    if (!(max > 0.0) || !std::isfinite(max)) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%g", max);
        throw Error(path, std::string("heatmap scale maximum ") + buf + " is not a finite number > 0");
    }
    const std::size_t count = map.width * map.height;
    if (map.width == 0 || map.height == 0 || map.values.size() != count || map.covered.size() != count)
        throw Error(path, "relMSE map size and value count disagree (or the map is empty)");
    std::vector<std::uint8_t> bytes(count * 3, 0);
    for (std::size_t i = 0; i < count; ++i) {
        if (!map.covered[i]) continue;  // black
        const std::array<std::uint8_t, 3> c = heatmap_colour(map.values[i], max);
        std::copy(c.begin(), c.end(), &bytes[i * 3]);
    }

    char description[128];
    std::snprintf(description, sizeof description,
                  "per-pixel relMSE, blue 0 to red %g and above (cyan, green, yellow between); black: not compared",
                  max);
    color::write_png_8bit(path, map.width, map.height, 3, bytes, {{"ImageDescription", description}});
}

}  // namespace npf::render
