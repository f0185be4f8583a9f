// MERL tables (`.binary`) as a material format: detection, loader (MerlBrdf, merl_brdf.cpp) and
// user documentation.
#include <npf/materials/material_formats.h>
#include <npf/materials/merl_brdf.h>

#include <npf/core/text.h>

namespace npf {

// MERL files by their size, or files that say they are one (their name, or a plausible header)
// whose size is wrong: the loader then says it is truncated or has trailing bytes.
MaterialFormat merl_material_format() {
    MaterialFormat f;
    f.described_as = "a MERL .binary";
    f.claims_file = [](const MaterialFileHead& h) {
        return MerlBrdf::looks_like_merl(h.bytes, h.count, h.size) || MerlBrdf::has_plausible_header(h.bytes, h.count, h.size) ||
               ends_with(h.path, ".binary");
    };
    f.open = [](const std::string& path) -> std::unique_ptr<Brdf> { return MerlBrdf::load(path); };
    f.title = "MERL `.binary` (`npf::MerlBrdf`, `materials/src/merl_brdf.cpp`)";
    f.documentation = R"(**Reads** the MERL database's isotropic RGB tables (Matusik et al. 2003), recognised by a size
that matches the dimensions in their header; a file whose header or name (`.binary`) says MERL
but whose size does not is named as truncated or as having trailing data.

The standard reader's layout (three int32 dimensions, then R, G, B blocks of float64, scales
1/1500, 1.15/1500, 1.66/1500, square-root theta_h index, phi_d folded to [0, pi)). Two lookups:
`Nearest` reproduces the standard reader's bins exactly; `Linear` interpolates between bin
centres (theta_h in its square-root coordinate, phi_d periodic over its folded period) and leaves
invalid (negative) bins out of the blend.

**Checks** positive dimensions whose table fills the file exactly, finite values, none beyond
1e12; negative stored numbers mark bins without a measurement.

**Limits.** MERL files carry no sampling tables, so `sample` is cosine-weighted
(pdf = cos(theta_o)/pi). A table holds at most 1 GiB. No real MERL file is available here; the
tests write files in the layout with known contents.

**Options:** the lookup (`npf::MerlOptions::lookup`, for `MerlBrdf::load`): `Nearest`, the
default and what `open_material` uses, or `Linear`.
)";
    return f;
}

}  // namespace npf
