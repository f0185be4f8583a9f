// RGL tensor files (`.bsdf`) as a material format: detection, loader (RglBrdf, rgl_brdf.cpp) and
// user documentation.
#include <npf/materials/material_formats.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/materials/tensor_file.h>

namespace npf {

MaterialFormat rgl_material_format() {
    MaterialFormat f;
    f.described_as = "an RGL tensor_file";
    f.claims_file = [](const MaterialFileHead& h) { return TensorFile::has_magic(h.bytes, h.count); };
    f.open = [](const std::string& path) -> std::unique_ptr<Brdf> { return RglBrdf::load(path); };
    f.title = "RGL `.bsdf` (`npf::RglBrdf`, `materials/src/rgl_brdf.cpp`)";
    f.documentation = R"(**Reads** the RGL group's measured materials (Dupuy & Jakob 2018), `tensor_file` containers
recognised by their magic bytes whatever their name: isotropic and anisotropic (phi_i reductions
1, 2 and 4), RGB (`rgb`) or spectral (`spectra` and `wavelengths`), with or without the
`jacobian` flag.

Follows the published algorithm of the RGL reference readers (powitacq, pbrt-v4's
`MeasuredBxDF`, Mitsuba 3's `measured`): the tensor_file container, the conditional
piecewise-bilinear tables (`npf::PiecewiseLinear2D`), `eval` = R · D / (4 σ), `pdf` and `sample`
through the luminance and VNDF warps, isotropic relative azimuth, anisotropic folding for
phi_i reductions 2 and 4 (Mitsuba 3's rule), spectral linear interpolation. The direction work
(angles, parameter blend, VNDF inversion) is done once per pair; every requested channel then
costs one blend of up to 16 stored values (8 for isotropic files).

**Checks** each field's type, rank and shape against the others; `phi_i`, `theta_i` and
`wavelengths` finite and strictly ascending, `theta_i` within [0, pi/2], an anisotropic `phi_i`
grid covering the interval folded queries land in; no non-finite value and none beyond 1e12 in
any table; `ndf` and `sigma` not negative; `jacobian` 0 or 1; `version`, when present, 1.0; a
`valid` mask of one bit per data node; not both `rgb` and `spectra`. A refusal is one line naming
the file and the field.

**Limits.** Negative (out-of-gamut) values are clamped to 0 when evaluated, for RGB and spectra
alike; `npf info` counts them and `npf eval --raw` / `npf render --raw` keep them. A file without
`jacobian` is read as `jacobian = 1`, as the reference readers do. The `valid` mask is shown by
`npf info` and not used by evaluation. One field holds at most 1 GiB.

**Options:** none.
)";
    return f;
}

}  // namespace npf
