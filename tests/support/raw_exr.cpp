#include "raw_exr.h"

#include <gtest/gtest.h>

namespace npf::testing {

std::vector<RawPart> read_raw(const std::string& path) {
    std::vector<RawPart> parts;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        ADD_FAILURE() << "cannot open " << path << ": " << OIIO::geterror();
        return parts;
    }
    for (int i = 0; in->seek_subimage(i, 0); ++i) {
        RawPart p;
        p.spec = in->spec();
        p.pixels.resize(std::size_t(p.spec.width) * std::size_t(p.spec.height) * std::size_t(p.spec.nchannels));
        EXPECT_TRUE(in->read_image(i, 0, 0, p.spec.nchannels, OIIO::TypeFloat, p.pixels.data())) << in->geterror();
        parts.push_back(std::move(p));
    }
    in->geterror();
    return parts;
}

void write_raw(const std::string& path, std::vector<RawPart> parts) {
    auto out = OIIO::ImageOutput::create("openexr");
    ASSERT_TRUE(out);
    std::vector<OIIO::ImageSpec> specs;
    for (RawPart& p : parts) {
        p.spec.format = OIIO::TypeFloat;
        p.spec.channelformats.clear();
        specs.push_back(p.spec);
    }
    ASSERT_TRUE(out->open(path, int(specs.size()), specs.data())) << out->geterror();
    for (std::size_t i = 0; i < parts.size(); ++i) {
        if (i > 0) {
            ASSERT_TRUE(out->open(path, specs[i], OIIO::ImageOutput::AppendSubimage)) << out->geterror();
        }
        ASSERT_TRUE(out->write_image(OIIO::TypeFloat, parts[i].pixels.data())) << out->geterror();
    }
    ASSERT_TRUE(out->close()) << out->geterror();
}

RawPart* find_raw(std::vector<RawPart>& parts, const std::string& name) {
    for (RawPart& p : parts) {
        if (p.spec.get_string_attribute("oiio:subimagename") == name) return &p;
    }
    ADD_FAILURE() << "no part " << name;
    return nullptr;
}

void set_value(RawPart& p, const std::string& channel, std::size_t pixel, float value) {
    const int c = p.spec.channelindex(channel);
    ASSERT_GE(c, 0) << channel;
    p.pixels[pixel * std::size_t(p.spec.nchannels) + std::size_t(c)] = value;
}

void drop_channel(RawPart& p, const std::string& channel) {
    const int drop = p.spec.channelindex(channel);
    ASSERT_GE(drop, 0) << channel;
    const std::size_t n = std::size_t(p.spec.width) * std::size_t(p.spec.height), nc = std::size_t(p.spec.nchannels);
    std::vector<float> kept;
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t c = 0; c < nc; ++c) {
            if (int(c) != drop) kept.push_back(p.pixels[i * nc + c]);
        }
    }
    p.pixels = kept;
    p.spec.channelnames.erase(p.spec.channelnames.begin() + drop);
    p.spec.nchannels -= 1;
}

}  // namespace npf::testing
