// The readers under fuzzing take file paths: each input is written to one scratch file per
// process (on a tmpfs when there is one) and read back from there.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

namespace npf::fuzz {

inline std::string scratch_file(const char* extension) {
    std::string dir = "/dev/shm";
    if (::access(dir.c_str(), W_OK) != 0) {
        const char* t = std::getenv("TMPDIR");
        dir = t && *t ? t : "/tmp";
    }
    return dir + "/npf-fuzz-" + std::to_string(::getpid()) + extension;
}

// Writes the bytes to `path`; false when it cannot (the input is then skipped).
inline bool write_scratch(const std::string& path, const std::uint8_t* data, std::size_t size) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return false;
    const bool ok = std::fwrite(data, 1, size, f) == size;
    return std::fclose(f) == 0 && ok;
}

}  // namespace npf::fuzz
