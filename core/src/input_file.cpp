#include <npf/core/error.h>
#include <npf/core/input_file.h>

#include <cerrno>
#include <cstring>
#include <sys/stat.h>

namespace npf {

void check_file_name(const std::string& path) {
    if (path.find('\0') != std::string::npos) throw Error(path, "a file name with a NUL byte: refused (the system would read another name)");
}

std::uint64_t require_regular_file(const std::string& path, const std::string& what) {
    check_file_name(path);
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) {
        throw Error(path, errno == ENOENT ? std::string("cannot open: file not found")
                                          : std::string("cannot open: ") + std::strerror(errno));
    }
    if (S_ISDIR(st.st_mode)) throw Error(path, "is a directory, not " + what);
    if (!S_ISREG(st.st_mode)) throw Error(path, "is not a regular file (expected " + what + ")");
    return std::uint64_t(st.st_size);
}

}  // namespace npf
