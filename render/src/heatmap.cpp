// relMSE heatmaps: a blue-cyan-green-yellow-red ramp, written as 8-bit PNG (docs/metrics.md).
#include <npf/render/heatmap.h>

#include <npf/core/atomic_file.h>
#include <npf/core/error.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace npf::render {

namespace {

std::string first_line(const std::string& s) {
    const std::size_t nl = s.find('\n');
    return nl == std::string::npos ? s : s.substr(0, nl);
}

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
    constexpr std::size_t kMaxSide = 1u << 20;  // PNG and OIIO take int sizes
    if (map.width > kMaxSide || map.height > kMaxSide) throw Error(path, "image too large for PNG");

    std::vector<std::uint8_t> bytes(count * 3, 0);
    for (std::size_t i = 0; i < count; ++i) {
        if (!map.covered[i]) continue;  // black
        const std::array<std::uint8_t, 3> c = heatmap_colour(map.values[i], max);
        std::copy(c.begin(), c.end(), &bytes[i * 3]);
    }

    AtomicOutput atomic(path);
    // The temporary name does not end in .png, so the format is named explicitly.
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("png");
    if (!out) throw Error(path, "this build of OpenImageIO cannot write PNG: " + first_line(OIIO::geterror()));
    OIIO::ImageSpec spec(static_cast<int>(map.width), static_cast<int>(map.height), 3, OIIO::TypeUInt8);
    char description[128];
    std::snprintf(description, sizeof description,
                  "per-pixel relMSE, blue 0 to red %g and above (cyan, green, yellow between); black: not compared",
                  max);
    spec.attribute("Software", "npf");
    spec.attribute("ImageDescription", description);
    if (!out->open(atomic.temporary_path(), spec))
        throw Error(path, "cannot create output: " + first_line(out->geterror()));
    if (!out->write_image(OIIO::TypeUInt8, bytes.data()))
        throw Error(path, "cannot write the pixels: " + first_line(out->geterror()));
    if (!out->close()) throw Error(path, "cannot finish output: " + first_line(out->geterror()));
    out.reset();
    atomic.commit();
}

}  // namespace npf::render
