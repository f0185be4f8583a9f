// The factor texture reader's seam between OpenEXR and npf's own checks (private to the
// library and its fuzz target): the parts of an open file as OpenImageIO describes them, and the
// reader that turns them into an NpfModel. The file (ImageInput) and a TextureSystem's cache are
// the two sources read_npf_texture uses; fuzz/fuzz_npf_parts.cpp feeds it parts made in memory,
// so that every check after OpenEXR is fuzzed at the speed of the checks themselves.
#pragma once

#include <npf/shading/npf_model.h>

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace npf {

// One part of the open file.
struct NpfTexturePart {
    int subimage = -1;
    OIIO::ImageSpec spec;
};

// Where the parts come from.
class NpfTexturePartSource {
public:
    virtual ~NpfTexturePartSource() = default;
    // Every part's header, in file order. Throws npf::Error naming the file.
    virtual std::vector<NpfTexturePart> parts() = 0;
    // All channels of a part as float, interleaved, width x height x nchannels values into
    // `pixels`; false with `why` on failure.
    virtual bool read(const NpfTexturePart& p, float* pixels, std::string& why) = 0;
};

// The two sources read_npf_texture uses (npf_texture_sources.cpp): the file, through
// OpenImageIO's ImageInput, and a TextureSystem's cache of it.
std::unique_ptr<NpfTexturePartSource> file_part_source(const std::string& path);
std::unique_ptr<NpfTexturePartSource> texture_system_part_source(const std::string& path, OIIO::TextureSystem& ts);

// The value of npf:tables_checksum for `model` (docs/format.md sec. 4; npf_texture_checksum.cpp): "fnv1a64:" and 16 lowercase
// hex digits, FNV-1a (64 bits) over every value the parts hold, part by part in the order D, G,
// F, spectral, detail, channel by channel in the order the format lists them, each channel's
// pixels in scanline order, as little-endian float32 bytes. The writer stores it; the reader
// recomputes it from what it read.
std::string tables_checksum(const NpfModel& model);

// Every check of docs/format.md sec. 8 over the parts `source` gives, naming `path` in the
// npf::Error it throws (also for a std::exception a source lets out). With `stored_bytes` (the
// file's size) also the expansion cap: the tables may take at most kMaxTableExpansion times the
// file's size plus kTableExpansionAllowance in memory, so that a small file of constant,
// highly compressible tables cannot cost gigabytes (docs/reliability.md, "Memory in proportion").
NpfModel read_npf_texture_parts(const std::string& path, std::unique_ptr<NpfTexturePartSource> source,
                                std::uint64_t stored_bytes = 0);
// Real factor textures hold 1.2 to 2.3 times their size in tables (float tables barely compress).
inline constexpr std::uint64_t kMaxTableExpansion = 16;
inline constexpr std::uint64_t kTableExpansionAllowance = std::uint64_t(16) << 20;

}  // namespace npf
