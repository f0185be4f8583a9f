#include <npf/converter/merl_brdf.h>
#include <npf/converter/open_brdf.h>
#include <npf/converter/rgl_brdf.h>
#include <npf/converter/tensor_file.h>
#include <npf/core/error.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sys/stat.h>

namespace npf {

std::unique_ptr<Brdf> open_brdf(const std::string& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) throw Error(path, std::string("cannot open: ") + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) throw Error(path, "is a directory, not a file");
    if (st.st_size == 0) throw Error(path, "empty file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, std::string("cannot open: ") + std::strerror(errno));
    std::uint8_t head[16] = {};
    in.read(reinterpret_cast<char*>(head), sizeof(head));
    const std::size_t got = std::size_t(in.gcount());
    if (TensorFile::has_magic(head, got)) return RglBrdf::load(path);
    if (MerlBrdf::looks_like_merl(head, got, std::uint64_t(st.st_size))) return MerlBrdf::load(path);
    throw Error(path, "unknown material format (neither an RGL tensor_file nor a MERL .binary)");
}

}  // namespace npf
