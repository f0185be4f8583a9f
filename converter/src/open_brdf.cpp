#include <npf/converter/analytic/analytic_brdf.h>
#include <npf/converter/material_recipe.h>
#include <npf/converter/merl_brdf.h>
#include <npf/converter/open_brdf.h>
#include <npf/converter/rgl_brdf.h>
#include <npf/converter/tensor_file.h>
#include <npf/core/error.h>
#include <npf/core/input_file.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_texture_file.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>

namespace npf {

std::unique_ptr<Brdf> open_brdf(const std::string& path) {
    const std::uint64_t size = require_regular_file(path);
    if (size == 0) throw Error(path, "empty file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, std::string("cannot open: ") + std::strerror(errno));
    std::uint8_t head[16] = {};
    in.read(reinterpret_cast<char*>(head), sizeof(head));
    const std::size_t got = std::size_t(in.gcount());
    if (TensorFile::has_magic(head, got)) return RglBrdf::load(path);
    if (MerlBrdf::looks_like_merl(head, got, size)) return MerlBrdf::load(path);
    // Any OpenEXR file is taken for an NPF texture: the reader says what is missing if it is not.
    if (has_exr_magic(head, got)) return std::make_unique<NpfBrdf>(path);
    throw Error(path, "unknown material format (not an RGL tensor_file, a MERL .binary or an NPF texture .exr)");
}

std::unique_ptr<Brdf> open_material(const std::string& path) {
    auto ends_with = [&](const char* tail) {
        const std::size_t n = std::strlen(tail);
        return path.size() >= n && path.compare(path.size() - n, n, tail) == 0;
    };
    if (ends_with(".yaml") || ends_with(".yml")) return std::make_unique<AnalyticBrdf>(load_material_recipe(path).material);
    return open_brdf(path);
}

}  // namespace npf
