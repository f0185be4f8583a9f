// A PNG read back for the tests of what writes them (heatmaps, display images, `npf display`):
// its size, channels and 8-bit values as stored. Alpha stays as stored (straight): OIIO would
// otherwise premultiply a PNG's alpha on reading.
#pragma once

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

namespace npf::testing {

struct Png {
    int width = 0, height = 0, channels = 0;
    std::vector<unsigned char> pixels;  // row by row, channel by channel
};

// A test failure and an empty Png where `path` cannot be read or is not a PNG.
inline Png read_png(const std::string& path) {
    OIIO::ImageSpec hints;
    hints.attribute("oiio:UnassociatedAlpha", 1);
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path, &hints);
    if (!in) {
        ADD_FAILURE() << "cannot read " << path << ": " << OIIO::geterror();
        return {};
    }
    EXPECT_EQ(in->format_name(), std::string("png"));
    const OIIO::ImageSpec& spec = in->spec();
    Png png;
    png.width = spec.width, png.height = spec.height, png.channels = spec.nchannels;
    png.pixels.resize(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
    EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeUInt8, png.pixels.data()));
    return png;
}

}  // namespace npf::testing
