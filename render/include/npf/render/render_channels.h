// What a render asks the material for, and how those values become linear Rec.709 pixels.
//
//  - RGB materials (and any material when RGB is requested) render in RGB: the material's linear
//    sRGB values times the environment's RGB radiance, channel by channel.
//  - Spectral materials render at a fixed wavelength quadrature (deterministic: no colour
//    noise). Per pixel the renderer estimates v_k = the integral over directions of
//    f_r cos * U(l_k) at each node l_k (U the environment's upsampled spectrum,
//    environment_spectra.h) and forms XYZ = sum_k W[c][k] v_k with W = npf::color::xyz_weights
//    (the nodes taken as a piecewise-linear spectrum, constant beyond the ends, integrated
//    against D65 x the CIE 1931 functions at 1 nm, normalised so that a flat 1 has Y = 1),
//    then linear Rec.709 = xyz_to_linear_srgb(XYZ); linear_srgb_weights folds both steps.
//    A flat spectrum c under a grey environment g therefore comes out as c g (1.00016, 0.99998,
//    0.99976): the D65 table's white, which npf does not renormalise (docs/color.md).
//  - Default nodes: the material's stored wavelengths, all of them, when at least 16 lie in
//    360..830 nm (querying exactly what is stored is the cheapest for every source: no
//    interpolation, and analytic materials use their precomputed tables only for exactly their
//    own list; nodes outside 360..830 nm get zero weight, or nearly, and are not looked up in
//    the environment); otherwise 360:830:95 (5 nm), the material interpolating between its own
//    wavelengths (docs/render.md).
#pragma once

#include <npf/core/brdf.h>
#include <npf/core/channels.h>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace npf::render {

struct RenderChannels {
    Channels channels;  // what the material is queried for
    // Spectral only: linear Rec.709 = sum_k to_rgb[c][k] v_k (3 rows of channels.size()).
    std::array<std::vector<double>, 3> to_rgb;
    bool spectral() const { return !channels.is_rgb(); }
};

// The quadrature nodes used by default for a material storing `stored` (spectral).
std::vector<float> default_render_wavelengths(const Channels& stored);

// Chooses the channels for `material`: `requested` when given (RGB, or wavelengths, which must
// be finite, within 300..1000 nm and ascending), else RGB for RGB materials and the default
// quadrature for spectral ones. Throws npf::Error naming `what` for bad wavelength lists.
// (Whether the material can provide them is checked by Brdf::query.)
RenderChannels choose_render_channels(const BrdfInfo& material, const std::optional<Channels>& requested,
                                      const std::string& what = "wavelengths");

}  // namespace npf::render
