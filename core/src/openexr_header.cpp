#include <npf/core/openexr_header.h>

#include <npf/core/error.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <vector>

namespace npf {

namespace {

// The headers of any real file are far smaller (a factor texture's, metadata included, a few
// KB); a file whose headers do not end within this many bytes is refused.
constexpr std::uint64_t kMaxHeaderBytes = std::uint64_t(16) << 20;
constexpr int kMaxParts = 1 << 12;
constexpr std::uint32_t kTiledFlag = 0x200, kLongNamesFlag = 0x400, kMultiPartFlag = 0x1000;

// OpenEXR reads an attribute of a known type with that type's own reader, whatever size the
// header declares, and then goes on from where that reader stopped: a declared size other than
// the type's makes it read the next attribute from the wrong place (a fuzzed file then had it
// allocate 1.8 GB for a 40 KB file). So those sizes must be exact.
const std::map<std::string, std::int32_t>& fixed_sizes() {
    static const std::map<std::string, std::int32_t> sizes = {
        {"int", 4},        {"float", 4},       {"double", 8},   {"rational", 8},      {"timecode", 8},
        {"v2i", 8},        {"v2f", 8},         {"v2d", 16},     {"v3i", 12},          {"v3f", 12},
        {"v3d", 24},       {"box2i", 16},      {"box2f", 16},   {"m33f", 36},         {"m33d", 72},
        {"m44f", 64},      {"m44d", 128},      {"compression", 1}, {"lineOrder", 1},  {"envmap", 1},
        {"deepImageState", 1}, {"tiledesc", 9}, {"keycode", 28}, {"chromaticities", 32},
    };
    return sizes;
}

std::int32_t le32(const std::uint8_t* p) {
    const std::uint32_t u = std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
                            std::uint32_t(p[3]) << 24;
    std::int32_t v;
    std::memcpy(&v, &u, 4);
    return v;
}

struct HeaderError {
    std::string why;
};

class Walker {
public:
    Walker(const std::uint8_t* bytes, std::size_t size, std::uint64_t file_size)
        : m_bytes(bytes), m_size(size), m_file_size(file_size) {}

    // A NUL-terminated name of at most `longest` characters; empty at the end of a header.
    std::string name(std::size_t longest, const char* what) {
        const std::size_t start = m_pos;
        while (m_pos < m_size && m_bytes[m_pos] != 0) {
            if (m_pos - start >= longest) fail(std::string(what) + " longer than " + std::to_string(longest) + " characters");
            ++m_pos;
        }
        if (m_pos >= m_size) truncated();
        return std::string(reinterpret_cast<const char*>(m_bytes + start), m_pos++ - start);
    }

    std::int32_t int32() {
        if (m_size - m_pos < 4) truncated();
        const std::int32_t v = le32(m_bytes + m_pos);
        m_pos += 4;
        return v;
    }

    const std::uint8_t* skip(const std::string& attribute, std::uint64_t n) {
        if (n > m_size - m_pos) {
            if (n > m_file_size - m_pos) {
                fail("attribute '" + attribute + "' claims " + std::to_string(n) + " bytes, more than the file holds");
            }
            truncated();
        }
        const std::uint8_t* p = m_bytes + m_pos;
        m_pos += std::size_t(n);
        return p;
    }

    bool at_end_of_headers() {
        if (m_pos >= m_size) truncated();
        if (m_bytes[m_pos] != 0) return false;
        ++m_pos;
        return true;
    }

    std::uint64_t position() const { return m_pos; }
    std::uint64_t file_size() const { return m_file_size; }

    [[noreturn]] void fail(const std::string& why) const { throw HeaderError{why}; }
    [[noreturn]] void truncated() const {
        if (m_size < m_file_size) fail("OpenEXR headers longer than " + std::to_string(m_size) + " bytes");
        fail("truncated OpenEXR header");
    }

private:
    const std::uint8_t* m_bytes;
    std::size_t m_size;
    std::uint64_t m_file_size;
    std::size_t m_pos = 8;
};

// A channel list: entries of name, pixel type (int), pLinear (1), reserved (3), x and y sampling
// (4 + 4), ended by an empty name that must be the list's last byte (OpenEXR reads up to it,
// not up to the declared size). OpenImageIO 2.4 aborts the process (an assertion) on a pixel
// type other than UINT, HALF or FLOAT (0, 1, 2), which OpenEXR passes on unchecked (fuzzing).
void check_channel_list(Walker& w, const std::uint8_t* list, std::size_t size) {
    std::size_t i = 0;
    while (i < size && list[i] != 0) {
        const std::uint8_t* end = static_cast<const std::uint8_t*>(std::memchr(list + i, 0, size - i));
        if (!end || std::size_t(end - list) + 17 > size) w.fail("malformed OpenEXR channel list");
        const std::size_t e = std::size_t(end - list);
        if (list[e + 1] > 2 || list[e + 2] != 0 || list[e + 3] != 0 || list[e + 4] != 0) {
            w.fail("OpenEXR channel '" + std::string(reinterpret_cast<const char*>(list + i), e - i) +
                   "' has an unknown pixel type");
        }
        i = e + 17;
    }
    if (i + 1 != size) w.fail("malformed OpenEXR channel list (its end is not where its size says)");
}

std::string walk(const std::uint8_t* bytes, std::size_t head_size, std::uint64_t file_size, std::uint64_t max_pixels) {
    if (head_size < 4 || !(bytes[0] == 0x76 && bytes[1] == 0x2f && bytes[2] == 0x31 && bytes[3] == 0x01)) {
        return "not an OpenEXR file";
    }
    if (head_size < 8) return "truncated OpenEXR header";
    const std::uint32_t flags = std::uint32_t(le32(bytes + 4));
    const bool multipart = flags & kMultiPartFlag, tiled = flags & kTiledFlag;
    const std::size_t longest = flags & kLongNamesFlag ? 255 : 31;
    Walker w(bytes, head_size, file_size);
    try {
        std::uint64_t chunk_entries = 0;  // offset-table entries of every part
        int parts = 0;
        do {
            if (++parts > kMaxParts) w.fail("more than " + std::to_string(kMaxParts) + " OpenEXR parts");
            bool has_window = false, has_chunk_count = false;
            std::uint64_t lines = 0;
            for (std::string attribute; !(attribute = w.name(longest, "an OpenEXR attribute name")).empty();) {
                const std::string type = w.name(longest, "an OpenEXR attribute type");
                const std::int32_t size = w.int32();
                if (size < 0) w.fail("OpenEXR attribute '" + attribute + "' has a negative size");
                const auto fixed = fixed_sizes().find(type);
                if (fixed != fixed_sizes().end() && size != fixed->second) {
                    w.fail("OpenEXR attribute '" + attribute + "' of type " + type + " has " + std::to_string(size) +
                           " bytes, not " + std::to_string(fixed->second));
                }
                const std::uint8_t* value = w.skip(attribute, std::uint64_t(size));
                if (type == "chlist") check_channel_list(w, value, std::size_t(size));
                if (type == "preview" &&
                    (size < 8 || std::uint64_t(size) != 8 + 4 * std::uint64_t(std::uint32_t(le32(value))) *
                                                               std::uint64_t(std::uint32_t(le32(value + 4))))) {
                    w.fail("OpenEXR preview image whose size disagrees with its pixels");
                }
                if (attribute == "dataWindow" && type == "box2i") {
                    const std::int64_t x0 = le32(value), y0 = le32(value + 4), x1 = le32(value + 8), y1 = le32(value + 12);
                    const std::int64_t width = x1 - x0 + 1, height = y1 - y0 + 1;
                    if (width < 1 || height < 1) w.fail("an empty or inverted OpenEXR data window");
                    if (std::uint64_t(width) * std::uint64_t(height) > max_pixels) {
                        w.fail("an OpenEXR data window of " + std::to_string(width) + " x " + std::to_string(height) +
                               " pixels, more than the " + std::to_string(max_pixels) + " this reader takes");
                    }
                    has_window = true;
                    lines = std::uint64_t(height);
                } else if (attribute == "chunkCount" && type == "int") {
                    const std::int32_t count = le32(value);
                    if (count < 0) w.fail("a negative OpenEXR chunk count");
                    chunk_entries += std::uint64_t(count);
                    has_chunk_count = true;
                }
            }
            if (!has_window) w.fail("an OpenEXR part without a data window");
            // Scanline parts without a chunkCount: at least one chunk per 256 lines (a lower bound).
            if (!has_chunk_count && !tiled) chunk_entries += (lines + 255) / 256;
            if (!multipart) break;
        } while (!w.at_end_of_headers());
        // The offset tables follow the headers, 8 bytes per chunk.
        if (chunk_entries > (w.file_size() - std::min(w.position(), w.file_size())) / 8) {
            w.fail("OpenEXR offset tables of " + std::to_string(chunk_entries) + " chunks do not fit in the file");
        }
    } catch (const HeaderError& e) {
        return e.why;
    }
    return "";
}

}  // namespace

std::string openexr_header_problem(const std::uint8_t* head, std::size_t head_size, std::uint64_t file_size,
                                   std::uint64_t max_pixels) {
    return walk(head, std::min<std::uint64_t>(head_size, file_size), std::max<std::uint64_t>(head_size, file_size),
                max_pixels);
}

std::string openexr_header_problem(const std::string& path, std::uint64_t max_pixels) {
    // Only the head of the file is read: the headers end within kMaxHeaderBytes or are refused.
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) return std::string("cannot open: ") + std::strerror(errno);
    const std::uint64_t file_size = std::uint64_t(in.tellg());
    in.seekg(0);
    std::vector<std::uint8_t> head(std::size_t(std::min(file_size, kMaxHeaderBytes)));
    if (!head.empty() && !in.read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size()))) {
        return "cannot read the OpenEXR headers";
    }
    return walk(head.data(), head.size(), file_size, max_pixels);
}

void check_openexr_header(const std::string& path, std::uint64_t max_pixels) {
    const std::string problem = openexr_header_problem(path, max_pixels);
    if (!problem.empty()) throw Error(path, problem);
}

}  // namespace npf
