// Raw OpenEXR editing for tests that make damaged or hostile factor textures: every part read as
// float pixels with its header, changed, and written again (no npf check on the way).
#pragma once

#include <OpenImageIO/imageio.h>

#include <cstddef>
#include <string>
#include <vector>

namespace npf::testing {

struct RawPart {
    OIIO::ImageSpec spec;
    std::vector<float> pixels;
};

std::vector<RawPart> read_raw(const std::string& path);
// Writes the parts as float, headers as they are (attributes included).
void write_raw(const std::string& path, std::vector<RawPart> parts);
// The part named `name` (OIIO's oiio:subimagename), or nullptr with a test failure.
RawPart* find_raw(std::vector<RawPart>& parts, const std::string& name);
void set_value(RawPart& p, const std::string& channel, std::size_t pixel, float value);
void drop_channel(RawPart& p, const std::string& channel);

}  // namespace npf::testing
