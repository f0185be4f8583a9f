// Scene-referred float images in, display-encoded 8-bit PNG files out (npf display, npf render).
#pragma once

#include <npf/color/display.h>
#include <npf/core/atomic_file.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace npf::color {

struct FloatImage {
    std::size_t width = 0, height = 0;
    int channels = 0;           // 3 (RGB or XYZ) or 4 (and alpha, premultiplied)
    std::vector<float> pixels;  // width * height * channels, rows top to bottom
};

// Reads the first image of a file OpenImageIO can read (OpenEXR above all) as float: its first
// three channels (R, G, B or X, Y, Z, in the file's order) and its alpha channel when the file
// marks one. Throws npf::Error naming the file: unreadable, or fewer than three channels.
FloatImage read_scene_image(const std::string& path);

// Writes `image` through `transform` (which says what the values are: linear Rec.709 or XYZ)
// as an 8-bit PNG at `path`: display values clamped to [0, 1], rounded to the nearest of 256
// levels. With 4 channels, alpha is taken as premultiplied (OpenEXR's convention): the colour
// is divided by it before the transform and the PNG stores straight alpha, as PNG requires.
// Published by npf::AtomicOutput (docs/reliability.md): complete or not at all. Throws
// npf::Error naming `path` (3 or 4 channels only, pixel count matching the size, unwritable
// folder, full disk); on failure the earlier file at `path` is untouched, nothing left beside it.
void write_display_png(const std::string& path, const FloatImage& image, const DisplayTransform& transform);
// The same into `out`, not committed: for publishing with another output (npf::commit_together).
void write_display_png(AtomicOutput& out, const FloatImage& image, const DisplayTransform& transform);

// The PNG writer under write_display_png, for images already in 8-bit display values (heatmaps,
// plots): `bytes` holds width * height * channels values, rows top to bottom; 3 channels or 4
// (straight alpha). `attributes` become text chunks (Software is npf). Atomic and throwing as
// write_display_png.
void write_png_8bit(const std::string& path, std::size_t width, std::size_t height, int channels,
                    const std::vector<std::uint8_t>& bytes,
                    const std::vector<std::pair<std::string, std::string>>& attributes = {});
void write_png_8bit(AtomicOutput& out, std::size_t width, std::size_t height, int channels,
                    const std::vector<std::uint8_t>& bytes,
                    const std::vector<std::pair<std::string, std::string>>& attributes = {});

}  // namespace npf::color
