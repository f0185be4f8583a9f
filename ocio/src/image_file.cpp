#include <npf/color/image_file.h>

#include <npf/core/error.h>
#include <npf/core/input_file.h>
#include <npf/core/openexr_header.h>
#include <npf/core/text.h>

#include <cstdint>
#include <cstring>
#include <fstream>

namespace npf::color {

namespace {

constexpr std::uint64_t kMaxPixels = std::uint64_t(1) << 28;
constexpr std::uint64_t kMaxExpansion = 64;
constexpr std::uint64_t kExpansionAllowance = std::uint64_t(64) << 20;

// OpenImageIO's name for the reader of a file that starts with `head`, or "" for none npf reads.
const char* format_of(const unsigned char* head, std::size_t n) {
    const auto starts = [&](const char* magic, std::size_t m) { return n >= m && std::memcmp(head, magic, m) == 0; };
    if (starts("\x76\x2f\x31\x01", 4)) return "openexr";
    if (starts("#?RADIANCE", 10) || starts("#?RGBE", 6)) return "hdr";
    if (starts("II*\0", 4) || starts("MM\0*", 4)) return "tiff";
    if (starts("\x89PNG\r\n\x1a\n", 8)) return "png";
    if (starts("\xff\xd8\xff", 3)) return "jpeg";
    return "";
}

}  // namespace

std::unique_ptr<OIIO::ImageInput> open_image_file(const std::string& path, const std::string& what) {
    const std::uint64_t bytes = require_regular_file(path, what);
    unsigned char head[16] = {};
    std::size_t got = 0;
    {
        std::ifstream in(path, std::ios::binary);
        in.read(reinterpret_cast<char*>(head), sizeof head);
        got = std::size_t(in.gcount());
    }
    const std::string format = format_of(head, got);
    if (format.empty()) throw Error(path, "not " + what + " npf reads (OpenEXR, Radiance HDR, TIFF, PNG or JPEG, by its first bytes)");
    if (format == "openexr") check_openexr_header(path, kMaxPixels);
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::create(format);
    if (!in) throw Error(path, "this build of OpenImageIO cannot read " + format + ": " + first_line(OIIO::geterror()));
    OIIO::ImageSpec spec;
    if (!in->open(path, spec)) throw Error(path, "cannot read " + what + ": " + first_line(in->geterror()));
    const OIIO::ImageSpec& s = in->spec();
    if (s.width <= 0 || s.height <= 0 || s.depth > 1) throw Error(path, what + " must be a 2D image");
    const std::uint64_t pixels = std::uint64_t(s.width) * std::uint64_t(s.height);
    const std::uint64_t floats = pixels * std::uint64_t(std::max(s.nchannels, 0)) * sizeof(float);
    if (pixels > kMaxPixels || floats > kMaxExpansion * bytes + kExpansionAllowance) {
        throw Error(path, std::to_string(s.width) + " x " + std::to_string(s.height) + " x " + std::to_string(s.nchannels) +
                              " would take " + std::to_string(floats >> 20) + " MiB as floats from a file of " +
                              std::to_string(bytes >> 10) + " KiB: at most 2^28 pixels and 64 times the file's size plus 64 MiB");
    }
    return in;
}

}  // namespace npf::color
