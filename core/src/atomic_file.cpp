#include <npf/core/atomic_file.h>
#include <npf/core/error.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <unistd.h>

namespace npf {

namespace {
std::string temporary_name_for(const std::string& path) {
    // Same folder (so rename is atomic), unique per process and call, recognisable if left over.
    static std::atomic<unsigned> counter{0};
    return path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
}

std::string system_message() { return std::strerror(errno); }
}  // namespace

void write_file_atomically(const std::string& path, const void* data, std::size_t size) {
    AtomicOutput out(path);
    std::FILE* f = std::fopen(out.temporary_path().c_str(), "wb");
    if (!f) throw Error(path, "cannot create temporary output: " + system_message());
    bool ok = size == 0 || std::fwrite(data, 1, size, f) == size;
    ok = (std::fflush(f) == 0) && ok;
    ok = (std::fclose(f) == 0) && ok;
    if (!ok) throw Error(path, "cannot write output: " + system_message());
    out.commit();
}

AtomicOutput::AtomicOutput(std::string path)
    : m_final(std::move(path)), m_temporary(temporary_name_for(m_final)) {}

AtomicOutput::~AtomicOutput() {
    if (!m_committed) std::remove(m_temporary.c_str());
}

void AtomicOutput::commit() {
    if (std::rename(m_temporary.c_str(), m_final.c_str()) != 0) {
        std::string why = system_message();
        std::remove(m_temporary.c_str());
        throw Error(m_final, "cannot move finished output into place: " + why);
    }
    m_committed = true;
}

}  // namespace npf
