// Content hashes for batch skipping: SHA-256 (FIPS 180-4) of bytes, files and text, as lowercase
// hex. Not a security boundary: a batch trusts its own output folder; the hash only has to change
// whenever an input, a setting or the tool's output format changes (docs/batch.md).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace npf::batch {

class Sha256 {
public:
    Sha256();
    void update(const void* data, std::size_t size);
    void update(const std::string& text) { update(text.data(), text.size()); }
    // The digest as 64 lowercase hex digits; the object must not be updated afterwards.
    std::string hex();

private:
    void block(const std::uint8_t* p);
    std::array<std::uint32_t, 8> m_state;
    std::array<std::uint8_t, 64> m_buffer{};
    std::size_t m_buffered = 0;
    std::uint64_t m_bytes = 0;
    bool m_done = false;
};

std::string sha256_hex(const std::string& text);
// The SHA-256 of a regular file's bytes. Throws npf::Error naming `path` when it cannot be read or
// is not a regular file (a FIFO or a device is never opened for reading).
std::string sha256_file(const std::string& path);

}  // namespace npf::batch
