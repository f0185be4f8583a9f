// The LUT files a display processor opens, checked before OCIO opens them (config_checks.h).
#include "config_checks.h"

#include <npf/color/display.h>
#include <npf/core/error.h>
#include <npf/core/file_kind.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace npf::color::detail {

namespace fs = std::filesystem;

std::vector<std::string> search_folders(const std::string& working, const std::vector<std::string>& search_paths) {
    std::vector<std::string> out;
    for (std::string p : search_paths) {
        const std::size_t b = p.find_first_not_of(" \t\r\n");
        const std::size_t e = p.find_last_not_of(" \t\r\n");
        p = b == std::string::npos ? std::string() : p.substr(b, e - b + 1);
        while (!p.empty() && p.back() == '/') p.pop_back();
        fs::path dir(p);
        if (!dir.is_absolute()) dir = fs::path(working) / dir;
        std::string normal = dir.lexically_normal().string();
        while (normal.size() > 1 && normal.back() == '/') normal.pop_back();
        out.push_back(normal);
    }
    if (out.empty()) out.push_back(working);
    return out;
}

namespace {

bool stat_exists(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0;
}

bool is_under(const fs::path& file, const fs::path& folder) {
    auto f = file.begin();
    for (auto d = folder.begin(); d != folder.end(); ++d, ++f) {
        if (d->empty() && std::next(d) == folder.end()) return true;  // a trailing '/'
        if (f == file.end() || *f != *d) return false;
    }
    return true;
}

// The first `size` bytes of a regular file, opened without blocking (it was a regular file when
// stat'ed; if it has been replaced by a FIFO since, the read does not wait for a writer).
std::string read_lut(const std::string& config_path, const std::string& label, const std::string& file) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) throw Error(config_path, label + " cannot be opened: " + std::strerror(errno));
    struct stat st;
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || std::uint64_t(st.st_size) > kMaxLutBytes) {
        ::close(fd);
        throw Error(config_path, label + " changed while it was checked: refused");
    }
    std::string bytes(std::size_t(st.st_size), '\0');
    std::size_t got = 0;
    while (got < bytes.size()) {
        const ssize_t n = ::read(fd, &bytes[got], bytes.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        got += std::size_t(n);
    }
    ::close(fd);
    bytes.resize(got);
    return bytes;
}

}  // namespace

// One LUT, resolved as Context::resolveFileLocation does: an absolute name as it is, a relative
// one in the first search folder where something by that name exists; OCIO then opens the
// lexically normalised path (so "x/../../y" leaves the folder without any x existing).
// Returns the file's size.
std::uint64_t check_lut(const std::string& config_path, const std::string& src, const std::string& resolved,
                        const std::vector<std::string>& folders) {
    const std::string name = "LUT " + quote(src);
    std::string opened;
    const bool absolute = !resolved.empty() && resolved.front() == '/';
    if (absolute) {
        if (stat_exists(resolved)) opened = fs::path(resolved).lexically_normal().string();
    } else if (!resolved.empty()) {
        for (const std::string& folder : folders) {
            const std::string full = (fs::path(folder) / resolved).string();
            if (!has_variables(full) && stat_exists(full)) {
                opened = fs::path(full).lexically_normal().string();
                break;
            }
        }
    }
    if (opened.empty())
        throw Error(config_path, name + " not found" +
                                     (absolute ? std::string() : " in the search path (" + join_quoted(folders) + ")"));
    const std::string label = name + " (" + opened + ")";
    struct stat st;
    if (::stat(opened.c_str(), &st) != 0) throw Error(config_path, label + " cannot be read: " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw Error(config_path, label + " is " + file_kind(st.st_mode) + ", not a regular file: refused");
    if (std::uint64_t(st.st_size) > kMaxLutBytes)
        throw Error(config_path, label + " is " + std::to_string(st.st_size) + " bytes, above npf's cap of " +
                                     std::to_string(kMaxLutBytes) + " (256 MiB) for a LUT: refused");
    std::error_code ec;
    const fs::path real = fs::canonical(opened, ec);
    bool inside = false;
    for (const std::string& folder : folders) {
        std::error_code fec;
        const fs::path real_folder = fs::canonical(folder, fec);
        if (!ec && !fec && is_under(real, real_folder)) inside = true;
    }
    if (!inside)
        throw Error(config_path, label + " lies outside the config's search path (" + join_quoted(folders) +
                                     (ec ? std::string() : "; it is " + real.string()) + "): refused");
    const std::string bytes = read_lut(config_path, label, opened);
    const std::string problem = lut_content_problem(bytes);
    if (!problem.empty()) throw Error(config_path, label + ": " + problem + ": refused");
    return bytes.size();
}


}  // namespace npf::color::detail
