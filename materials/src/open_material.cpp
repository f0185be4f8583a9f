#include <npf/materials/material_formats.h>
#include <npf/materials/open_material.h>

#include <npf/core/error.h>
#include <npf/core/input_file.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>

namespace npf {

std::unique_ptr<Brdf> open_material(const std::string& path) {
    const std::vector<MaterialFormat>& formats = material_formats();
    for (const MaterialFormat& f : formats)
        if (f.claims_name && f.claims_name(path)) return f.open(path);
    // Any other file by its contents.
    const std::uint64_t size = require_regular_file(path);
    if (size == 0) throw Error(path, "empty file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, std::string("cannot open: ") + std::strerror(errno));
    std::uint8_t bytes[kMaterialHeadBytes] = {};
    in.read(reinterpret_cast<char*>(bytes), sizeof(bytes));
    const MaterialFileHead head{path, bytes, std::size_t(in.gcount()), size};
    for (const MaterialFormat& f : formats)
        if (f.claims_file && f.claims_file(head)) return f.open(path);
    throw Error(path, "unknown material format (not " + material_format_list() + ")");
}

}  // namespace npf
