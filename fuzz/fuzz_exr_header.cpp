// libFuzzer target, in memory: the OpenEXR header walk that guards every npf reader of OpenEXR
// files (core/openexr_header.h) and, for headers it accepts, OpenEXR's own header and offset
// table reading over the same bytes. The walk's promise is what this checks at speed: a file it
// accepts makes OpenEXR allocate no more than the file can justify (-malloc_limit_mb) and never
// crash. Pixels are decoded by the slower whole-reader target (npf_fuzz_npf_exr).
#include <npf/core/openexr_header.h>

#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfMultiPartInputFile.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <exception>

namespace {

// The fuzzer's bytes as an OpenEXR input stream.
class MemoryStream final : public Imf::IStream {
public:
    MemoryStream(const std::uint8_t* data, std::size_t size) : Imf::IStream("fuzz.exr"), m_data(data), m_size(size) {}

    bool read(char c[], int n) override {
        if (n < 0 || std::uint64_t(n) > m_size - std::min<std::uint64_t>(m_pos, m_size)) {
            throw std::runtime_error("read past the end");
        }
        std::memcpy(c, m_data + m_pos, std::size_t(n));
        m_pos += std::uint64_t(n);
        return m_pos < m_size;
    }
    std::uint64_t tellg() override { return m_pos; }
    void seekg(std::uint64_t pos) override { m_pos = pos; }

private:
    const std::uint8_t* m_data;
    std::uint64_t m_size;
    std::uint64_t m_pos = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // The factor texture reader's pixel cap (npf_texture_file.cpp), the strictest of the callers.
    if (!npf::openexr_header_problem(data, size, size, std::uint64_t(1) << 23).empty()) return 0;
    try {
        MemoryStream stream(data, size);
        Imf::MultiPartInputFile file(stream, 1);
        for (int i = 0; i < file.parts(); ++i) (void)file.header(i).dataWindow();
    } catch (const std::exception&) {
    }
    return 0;
}
