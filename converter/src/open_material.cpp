#include <npf/converter/analytic/analytic_brdf.h>
#include <npf/converter/material_recipe.h>
#include <npf/converter/merl_brdf.h>
#include <npf/converter/nbrdf_brdf.h>
#include <npf/converter/open_material.h>
#include <npf/converter/rgl_brdf.h>
#include <npf/converter/tensor_file.h>
#include <npf/core/error.h>
#include <npf/core/input_file.h>
#include <npf/core/text.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_texture_file.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>

namespace npf {

namespace {

// A file that is not a recipe, by its contents.
std::unique_ptr<Brdf> open_material_file(const std::string& path) {
    const std::uint64_t size = require_regular_file(path);
    if (size == 0) throw Error(path, "empty file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, std::string("cannot open: ") + std::strerror(errno));
    std::uint8_t head[16] = {};
    in.read(reinterpret_cast<char*>(head), sizeof(head));
    const std::size_t got = std::size_t(in.gcount());
    if (TensorFile::has_magic(head, got)) return RglBrdf::load(path);
    // A MERL file by its size, or one that says it is (its name, or a plausible header) whose
    // size is wrong: the loader then says it is truncated or has trailing bytes.
    if (MerlBrdf::looks_like_merl(head, got, size) || MerlBrdf::has_plausible_header(head, got, size) ||
        ends_with(path, ".binary"))
        return MerlBrdf::load(path);
    // Any OpenEXR file is taken for an NPF texture: the reader says what is missing if it is not;
    // so is a TIFF, which the reader names as maketx's copy of one (docs/farms.md).
    if (has_exr_magic(head, got) || has_tiff_magic(head, got)) return std::make_unique<NpfBrdf>(path);
    // Any HDF5 file, or any file named like one, is taken for a Neural BRDF network: the reader
    // says what is missing (or that it is not HDF5 at all).
    if (NbrdfBrdf::has_hdf5_signature(head, got) || ends_with(path, ".h5") || ends_with(path, ".hdf5"))
        return NbrdfBrdf::load(path);
    throw Error(path, "unknown material format (not an RGL tensor_file, a MERL .binary, an NPF "
                      "texture .exr or a Neural BRDF .h5)");
}

}  // namespace

std::unique_ptr<Brdf> open_material(const std::string& path) {
    if (ends_with(path, ".yaml") || ends_with(path, ".yml")) {
        const MaterialRecipe recipe = load_material_recipe(path);
        try {
            return std::make_unique<AnalyticBrdf>(recipe.material);
        } catch (const Error& e) {
            throw Error(path, e.problem());  // named by the recipe's file, not its material's name
        }
    }
    return open_material_file(path);
}

}  // namespace npf
