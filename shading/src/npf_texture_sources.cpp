// The two part sources read_npf_texture uses (npf_texture_parts.h): the file through
// OpenImageIO's ImageInput, and a TextureSystem's cache.
#include "npf_texture_parts.h"

#include <npf/core/error.h>
#include <npf/core/text.h>

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <algorithm>

namespace npf {

namespace {

using OIIO::ImageSpec;
using Part = NpfTexturePart;
using PartSource = NpfTexturePartSource;

class FileSource final : public PartSource {
public:
    explicit FileSource(const std::string& path) : m_path(path) {}

    std::vector<Part> parts() override {
        m_input = OIIO::ImageInput::create("openexr");
        if (!m_input) throw Error(m_path, "this build of OpenImageIO cannot read OpenEXR: " + OIIO::geterror());
        ImageSpec spec;
        if (!m_input->open(m_path, spec)) {
            throw Error(m_path, "cannot read the OpenEXR headers: " + first_line(m_input->geterror()));
        }
        // The header says how many parts there are: a part OpenImageIO refuses (more channels than
        // its limits:channels, say) is named with its reason, not taken for a missing part.
        const int count = spec.get_int_attribute("oiio:subimages", 1);
        std::vector<Part> parts;
        for (int i = 0; i < count; ++i) {
            if (!m_input->seek_subimage(i, 0))
                throw Error(m_path, "OpenImageIO cannot open part " + std::to_string(i + 1) + " of " + std::to_string(count) + ": " +
                                        first_line(m_input->geterror()));
            Part p;
            p.subimage = i;
            p.spec = m_input->spec();
            parts.push_back(std::move(p));
        }
        // (OpenEXR itself guarantees that part names are unique.)
        return parts;
    }

    bool read(const Part& p, float* pixels, std::string& why) override {
        const bool ok = m_input->read_image(p.subimage, 0, 0, p.spec.nchannels, OIIO::TypeFloat, pixels);
        if (!ok) why = first_line(m_input->geterror());
        return ok;
    }

private:
    std::string m_path;
    std::unique_ptr<OIIO::ImageInput> m_input;
};

class TextureSystemSource final : public PartSource {
public:
    TextureSystemSource(const std::string& path, OIIO::TextureSystem& ts) : m_path(path), m_name(path), m_ts(ts) {}

    std::vector<Part> parts() override {
        int count = 0;
        if (!m_ts.get_texture_info(m_name, 0, OIIO::ustring("subimages"), OIIO::TypeInt, &count) || count < 1) {
            throw Error(m_path, "the TextureSystem cannot open it: " + first_line(m_ts.geterror()));
        }
        std::vector<Part> parts;
        for (int i = 0; i < count; ++i) {
            Part p;
            p.subimage = i;
            if (!m_ts.get_imagespec(m_name, i, p.spec)) {
                throw Error(m_path, "the TextureSystem cannot read part " + std::to_string(i) + ": " +
                                        first_line(m_ts.geterror()));
            }
            parts.push_back(std::move(p));
        }
        return parts;
    }

    bool read(const Part& p, float* pixels, std::string& why) override {
        OIIO::TextureOpt opt;
        opt.subimage = p.subimage;
        const ImageSpec& s = p.spec;
        const bool ok = m_ts.get_texels(m_name, opt, 0, s.x, s.x + s.width, s.y, s.y + s.height, s.z,
                                        s.z + std::max(s.depth, 1), 0, s.nchannels, OIIO::TypeFloat, pixels);
        if (!ok) why = first_line(m_ts.geterror());
        return ok;
    }

private:
    std::string m_path;
    OIIO::ustring m_name;
    OIIO::TextureSystem& m_ts;
};

}  // namespace

std::unique_ptr<NpfTexturePartSource> file_part_source(const std::string& path) {
    return std::make_unique<FileSource>(path);
}

std::unique_ptr<NpfTexturePartSource> texture_system_part_source(const std::string& path, OIIO::TextureSystem& ts) {
    return std::make_unique<TextureSystemSource>(path, ts);
}

}  // namespace npf
