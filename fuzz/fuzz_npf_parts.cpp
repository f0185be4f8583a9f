// libFuzzer target, in memory: every check the factor texture reader makes after OpenEXR, at the
// speed of the checks. Decoding OpenEXR costs about a millisecond an input, so the whole-reader
// target (npf_fuzz_npf_exr) reaches thousands of inputs where this one reaches millions; the
// OpenEXR side is fuzzed in memory by npf_fuzz_exr_header. Here the fuzzer's bytes are a script
// of edits to real factor textures decoded once at start: attributes set to other values and
// types or removed, parts renamed, dropped, repeated or reordered, sizes and channel lists
// changed, pixel values replaced, a part's pixels cut short or failing to decode. Each result is
// read by the reader's own code (read_npf_texture_parts). Accepted models are not shaded here:
// building the closure (the albedo quadrature of NpfModel::prepare) costs about fifteen times the
// reading; the whole-reader target shades what it accepts.
//
// Every edit keeps what OpenImageIO itself guarantees of an ImageSpec (one name and at most one
// format per channel), so that a finding is one a file could cause.
#include "../shading/src/npf_texture_parts.h"

#include <npf/core/error.h>
#include <npf/shading/npf_texture_file.h>
#include <npf/shading/npf_texture_layout.h>

#include <OpenImageIO/imageio.h>

#include <fuzzer/FuzzedDataProvider.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace {

namespace layout = npf::npf_exr;

struct MemoryPart {
    OIIO::ImageSpec spec;
    std::vector<float> pixels;  // interleaved, as the file decodes
    bool fails = false;         // decoding fails (a corrupt chunk)
};
using Texture = std::vector<MemoryPart>;

std::vector<Texture>& base_textures() {
    static std::vector<Texture> textures;
    return textures;
}

// Decodes every part of a real factor texture.
Texture decode(const std::string& path) {
    Texture t;
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
    if (!in) return t;
    for (int i = 0; in->seek_subimage(i, 0); ++i) {
        MemoryPart p;
        p.spec = in->spec();
        p.pixels.resize(std::size_t(p.spec.width) * std::size_t(p.spec.height) * std::size_t(p.spec.nchannels));
        if (!in->read_image(i, 0, 0, p.spec.nchannels, OIIO::TypeFloat, p.pixels.data())) return {};
        t.push_back(std::move(p));
    }
    in->geterror();
    return t;
}

class MemorySource final : public npf::NpfTexturePartSource {
public:
    explicit MemorySource(const Texture& parts) : m_parts(parts) {}

    std::vector<npf::NpfTexturePart> parts() override {
        std::vector<npf::NpfTexturePart> out;
        for (std::size_t i = 0; i < m_parts.size(); ++i) out.push_back({int(i), m_parts[i].spec});
        return out;
    }

    bool read(const npf::NpfTexturePart& p, float* pixels, std::string& why) override {
        const MemoryPart& m = m_parts.at(std::size_t(p.subimage));
        const OIIO::ImageSpec& s = p.spec;
        const std::size_t wanted = std::size_t(std::max(s.width, 0)) * std::size_t(std::max(s.height, 0)) *
                                   std::size_t(std::max(s.nchannels, 0));
        if (m.fails || m.pixels.size() < wanted) {
            why = "decoding failed";
            return false;
        }
        std::copy(m.pixels.begin(), m.pixels.begin() + std::ptrdiff_t(wanted), pixels);
        return true;
    }

private:
    const Texture& m_parts;
};

const char* const kAttributeNames[] = {
    layout::kAttrVersion,          layout::kAttrChannelKind,     layout::kAttrChannelCount,
    layout::kAttrIsotropic,        layout::kAttrDTheta,          layout::kAttrDPhi,
    layout::kAttrFTheta,           layout::kAttrGTheta,          layout::kAttrGPhi,
    layout::kAttrDRank,            layout::kAttrGRank,           layout::kAttrDKeptRatio,
    layout::kAttrGKeptRatio,       layout::kAttrDSingularValues, layout::kAttrGSingularValues,
    layout::kAttrDetailThetaH,     layout::kAttrDetailThetaD,    layout::kAttrDetailPhiD,
    layout::kAttrDetailRank,       layout::kAttrDetailKeptRatio, layout::kAttrDetailSingularValues,
    layout::kAttrMetadataKeys,     "npf:meta:source",            "npf:meta:",
    "oiio:subimagename"};
const char* const kPartNames[] = {layout::kPartD, layout::kPartG, layout::kPartF, layout::kPartSpectral,
                                  layout::kPartDetail, "", "d"};
const char* const kChannelPrefixes[] = {layout::kDBasis, layout::kGBasis, layout::kFChannel, layout::kDWeight,
                                        layout::kGWeight, layout::kRBasis, layout::kRWeight};

int edge_int(FuzzedDataProvider& in) {
    static const int kEdges[] = {0, 1, 2, 3, 4, 7, 8, -1, 65535, 65536, 65537, 1 << 20, INT_MAX, INT_MIN};
    return in.ConsumeBool() ? in.PickValueInArray(kEdges) : in.ConsumeIntegralInRange(-4, 300);
}

float edge_float(FuzzedDataProvider& in) {
    static const float kEdges[] = {0.f, -0.f, -1.f, 1.f, 1e-45f, 3e38f, -3e38f, std::numeric_limits<float>::infinity(),
                                   -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()};
    return in.ConsumeBool() ? in.PickValueInArray(kEdges) : in.ConsumeFloatingPoint<float>();
}

std::string some_text(FuzzedDataProvider& in) {
    static const char* const kTexts[] = {"rgb", "spectral", "", "1 2 3", "1e999 0", "nan", "0.5 0.25 0.125 0.0625",
                                         "source\nsource", "a\n\nb", "\n"};
    return in.ConsumeBool() ? std::string(in.PickValueInArray(kTexts)) : in.ConsumeRandomLengthString(48);
}

// Renames channel `c`, adds one (with a name from the format's families) or removes one, with
// the pixels kept in step.
void edit_channels(FuzzedDataProvider& in, MemoryPart& p) {
    OIIO::ImageSpec& s = p.spec;
    const std::size_t pixels = std::size_t(std::max(s.width, 0)) * std::size_t(std::max(s.height, 0));
    // Channels are added or removed with the pixels kept in step, which needs a part whose size
    // still matches its pixels (not one an earlier edit made claim 2^31 columns).
    const bool in_step = pixels <= (std::size_t(1) << 20) && p.pixels.size() == pixels * std::size_t(std::max(s.nchannels, 0));
    const int n = s.nchannels;
    const int c = n > 0 ? in.ConsumeIntegralInRange(0, n - 1) : 0;
    std::string name = in.ConsumeBool() ? layout::indexed_channel(in.PickValueInArray(kChannelPrefixes),
                                                                  in.ConsumeIntegralInRange<std::size_t>(0, 12),
                                                                  in.ConsumeIntegralInRange<std::size_t>(1, 200))
                                        : some_text(in);
    switch (in.ConsumeIntegralInRange(0, 3)) {
    case 0:
        if (n > 0) s.channelnames[std::size_t(c)] = name;
        break;
    case 1: {  // a new last channel
        if (n >= 4096 || !in_step) break;
        std::vector<float> grown(pixels * std::size_t(n + 1));
        for (std::size_t i = 0; i < pixels; ++i) {
            std::copy_n(p.pixels.begin() + std::ptrdiff_t(i * std::size_t(n)), n, grown.begin() + std::ptrdiff_t(i * std::size_t(n + 1)));
            grown[i * std::size_t(n + 1) + std::size_t(n)] = edge_float(in);
        }
        p.pixels = std::move(grown);
        s.channelnames.push_back(name);
        if (!s.channelformats.empty()) s.channelformats.push_back(s.format);
        s.nchannels = n + 1;
        break;
    }
    case 2: {  // channel c removed
        if (n == 0 || !in_step) break;
        std::vector<float> shrunk;
        shrunk.reserve(pixels * std::size_t(n - 1));
        for (std::size_t i = 0; i < p.pixels.size(); ++i) {
            if (int(i % std::size_t(n)) != c) shrunk.push_back(p.pixels[i]);
        }
        p.pixels = std::move(shrunk);
        s.channelnames.erase(s.channelnames.begin() + c);
        if (!s.channelformats.empty()) s.channelformats.erase(s.channelformats.begin() + c);
        s.nchannels = n - 1;
        break;
    }
    default: {  // channel c stored in another pixel type
        if (n == 0) break;
        static const OIIO::TypeDesc kTypes[] = {OIIO::TypeHalf, OIIO::TypeFloat, OIIO::TypeUInt, OIIO::TypeDesc::DOUBLE};
        if (s.channelformats.empty()) s.channelformats.assign(std::size_t(n), s.format);
        s.channelformats[std::size_t(c)] = in.PickValueInArray(kTypes);
        break;
    }
    }
}

void edit_attribute(FuzzedDataProvider& in, OIIO::ImageSpec& s) {
    const std::string name = in.ConsumeBool() ? std::string(in.PickValueInArray(kAttributeNames))
                                              : "npf:meta:" + in.ConsumeRandomLengthString(12);
    switch (in.ConsumeIntegralInRange(0, 4)) {
    case 0: s.attribute(name, edge_int(in)); break;
    case 1: s.attribute(name, edge_float(in)); break;
    case 2: {
        const double v = edge_float(in);
        s.attribute(name, OIIO::TypeDesc::DOUBLE, &v);
        break;
    }
    case 3: s.attribute(name, some_text(in)); break;
    // Not ImageSpec::erase_attribute: it takes a regular expression, and a random name is one
    // that backtracks for ever inside OpenImageIO (a harness timeout, not a reader's fault).
    default: s.extra_attribs.remove(name, OIIO::TypeDesc::UNKNOWN, /*casesensitive=*/true); break;
    }
}

void edit(FuzzedDataProvider& in, Texture& t) {
    if (t.empty()) return;
    MemoryPart& p = t[in.ConsumeIntegralInRange<std::size_t>(0, t.size() - 1)];
    switch (in.ConsumeIntegralInRange(0, 9)) {
    case 0:
    case 1: edit_attribute(in, p.spec); break;
    case 2: p.spec.attribute("oiio:subimagename", in.ConsumeBool() ? in.PickValueInArray(kPartNames) : some_text(in)); break;
    case 3: {  // a part dropped, repeated or moved
        const std::size_t i = in.ConsumeIntegralInRange<std::size_t>(0, t.size() - 1);
        const int how = in.ConsumeIntegralInRange(0, 2);
        if (how == 0) {
            t.erase(t.begin() + std::ptrdiff_t(i));
        } else if (how == 1 && t.size() < 12) {
            t.push_back(t[i]);
        } else {
            std::swap(t[i], t[in.ConsumeIntegralInRange<std::size_t>(0, t.size() - 1)]);
        }
        break;
    }
    case 4: {  // sizes that disagree with the pixels and the attributes
        const int v = edge_int(in);
        switch (in.ConsumeIntegralInRange(0, 2)) {
        case 0: p.spec.width = v; break;
        case 1: p.spec.height = v; break;
        default: p.spec.depth = v; break;
        }
        p.spec.full_width = p.spec.width;
        p.spec.full_height = p.spec.height;
        break;
    }
    case 5:
    case 6: edit_channels(in, p); break;
    case 7:
    case 8:
        if (!p.pixels.empty()) p.pixels[in.ConsumeIntegralInRange<std::size_t>(0, p.pixels.size() - 1)] = edge_float(in);
        break;
    default:
        if (in.ConsumeBool()) {
            p.fails = true;
        } else {
            p.pixels.resize(in.ConsumeIntegralInRange<std::size_t>(0, p.pixels.size()));
        }
        break;
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    OIIO::attribute("threads", 1);
    const char* dir = std::getenv("NPF_FUZZ_TEXTURES");
    const std::filesystem::path folder = dir ? dir : NPF_FUZZ_TEXTURES;
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        if (entry.path().extension() == ".exr") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());  // the input picks a texture by index: keep it stable
    for (const auto& f : files) {
        Texture t = decode(f.string());
        if (t.empty()) continue;
        // Unedited, every seed must read: otherwise only the error paths would be fuzzed.
        try {
            (void)npf::read_npf_texture_parts(f.string(), std::make_unique<MemorySource>(t));
        } catch (const npf::Error& e) {
            std::fprintf(stderr, "npf_fuzz_npf_parts: a seed does not read: %s\n", e.what());
            std::abort();
        }
        base_textures().push_back(std::move(t));
    }
    if (base_textures().empty()) {
        std::fprintf(stderr, "npf_fuzz_npf_parts: no factor textures in %s (NPF_FUZZ_TEXTURES)\n", folder.c_str());
        std::abort();
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);
    const std::vector<Texture>& bases = base_textures();
    Texture texture = bases[in.ConsumeIntegralInRange<std::size_t>(0, bases.size() - 1)];
    const int edits = in.ConsumeIntegralInRange(0, 8);
    for (int i = 0; i < edits && in.remaining_bytes() > 0; ++i) edit(in, texture);
    try {
        (void)npf::read_npf_texture_parts("fuzz.exr", std::make_unique<MemorySource>(texture));
    } catch (const npf::Error&) {
    }
    return 0;
}
