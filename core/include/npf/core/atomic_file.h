// Outputs appear whole or not at all: everything the project writes goes to a temporary file
// beside the destination and is renamed over it only once complete. A crash or Ctrl-C leaves
// at worst a stray temporary, never a half-written output under the real name.
#pragma once

#include <cstddef>
#include <string>

namespace npf {

// Writes `size` bytes to `path` atomically. Throws npf::Error naming `path`.
void write_file_atomically(const std::string& path, const void* data, std::size_t size);

// For writers that need a file name (OpenImageIO, ...): hands out a temporary name beside
// `path`; commit() renames it over `path`; the destructor removes it if commit() never ran.
class AtomicOutput {
public:
    explicit AtomicOutput(std::string path);
    ~AtomicOutput();
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;

    const std::string& temporary_path() const { return m_temporary; }
    const std::string& final_path() const { return m_final; }
    void commit();  // throws npf::Error naming the final path

private:
    std::string m_final;
    std::string m_temporary;
    bool m_committed = false;
};

}  // namespace npf
