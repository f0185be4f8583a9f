// NPF factor textures (docs/format.md) as a material format: the reader is shading's (NpfBrdf).
#include <npf/materials/material_formats.h>

#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_texture_file.h>

namespace npf {

// Any OpenEXR file is taken for an NPF texture: the reader says what is missing if it is not; so
// is a TIFF, which the reader names as maketx's copy of one (docs/farms.md).
MaterialFormat npf_texture_material_format() {
    MaterialFormat f;
    f.described_as = "an NPF texture .exr";
    f.claims_file = [](const MaterialFileHead& h) { return has_exr_magic(h.bytes, h.count) || has_tiff_magic(h.bytes, h.count); };
    f.open = [](const std::string& path) -> std::unique_ptr<Brdf> { return std::make_unique<NpfBrdf>(path); };
    return f;
}

}  // namespace npf
