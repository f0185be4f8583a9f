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
    f.title = "NPF factor textures `.exr` (`npf::NpfBrdf`, `shading/src/npf_brdf.cpp`)";
    f.documentation = R"(**Reads** the factor textures `npf convert` writes (docs/format.md), format versions 1 and 2,
recognised by OpenEXR's magic bytes; a TIFF is recognised too, to be named as maketx's copy of one
(docs/farms.md).

**Checks** everything docs/format.md section 8 lists, before anything large is allocated: the
format version, every attribute, part and channel the version needs, grid sizes within the size
caps, pixel types, no NaN or infinity, non-negative factors, ascending wavelengths, and the tables
against `npf:tables_checksum`. What image tools make of a factor texture (a TIFF, a single-part
copy, half pixels, a changed checksum) is named as such, pointing to the original.

**Limits.** The size caps of docs/format.md section 8, and the value bound of every material
source (1e12).

**Options:** the evaluation path, memory (tables in arrays, the default and what `open_material`
uses) or texture (lookups through OpenImageIO's TextureSystem, `npf eval --path texture`).
)";
    return f;
}

}  // namespace npf
