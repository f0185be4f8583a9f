// Diffuse and specular colour edits (paper secs. 4.3.2 and 4.3.3). Neither touches D or G (their
// bases and weights are copied bit for bit); the diffuse edit touches rho_d only, the specular
// one rho_s and F only.
//
// Channels: a colour from a source with other channels is converted (docs/editing.md):
// spectral to spectral by linear interpolation in wavelength (constant beyond the source's
// range), spectral to RGB by its colour (linear sRGB under D65), RGB to spectral by the smooth
// sigmoid upsampling of npf/color/rgb_sigmoid.h.
#pragma once

#include <npf/color/spectrum.h>
#include <npf/edit/edit_record.h>
#include <npf/shading/npf_model.h>

namespace npf::edit {

// rho_d of `from` (any NPF material, isotropic or not, RGB or spectral), times `scale`.
NpfModel replace_diffuse(const NpfModel& model, const NpfModel& from, double scale = 1.0, EditRecord* record = nullptr);
// A diffuse albedo (the Lambertian term's reflectance, in [0, 1] for a physical material):
// rho_d = albedo / pi. A spectrum is sampled at a spectral model's wavelengths (linear, constant
// beyond its ends) or turned into its colour for an RGB model; a linear sRGB colour is taken as
// it is by an RGB model and upsampled for a spectral one.
NpfModel replace_diffuse_albedo(const NpfModel& model, const color::SampledSpectrum& albedo, EditRecord* record = nullptr);
NpfModel replace_diffuse_albedo(const NpfModel& model, const color::Rgb& linear_albedo, EditRecord* record = nullptr);

struct SpecularSwap {
    double scale = 1.0;
    // Scale the new rho_s F so that its luminance at normal incidence (CIE Y of rho_s F(0)) is the
    // material's own: the colour and the Fresnel curve change, the brightness does not. `scale`
    // applies on top.
    bool keep_brightness = false;
};

// The specular colour rho_s F(theta_d) of `from`; D and G (the highlight's shape) stay. F is
// resampled onto the model's theta_d grid (linear between centres, clamped) when the grids
// differ, and the result is put back in the gauge (F = 1 in the first theta_d cell).
// rho_s carries the scale that the fitter's gauge gives it together with D and G: between two
// microfacet-like materials (G near Smith's) it is F0 / 4 in both, but a material whose G grows
// towards grazing (fabrics) has a small rho_s, and another material's rho_s on its G can exceed
// albedo 1 (the albedo check reports it; keep_brightness avoids it).
NpfModel replace_specular(const NpfModel& model, const NpfModel& from, const SpecularSwap& swap = {},
                          EditRecord* record = nullptr);

}  // namespace npf::edit
