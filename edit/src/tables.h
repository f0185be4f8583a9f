// Helpers shared by the edits (private to the module): per-channel tables reconstructed from
// the SVD bases, re-compression, and moving per-channel quantities between channel sets.
#pragma once

#include <npf/fit/npf_factors.h>
#include <npf/core/channels.h>
#include <npf/edit/edit_record.h>
#include <npf/edit/ndf_transform.h>
#include <npf/shading/npf_model.h>

#include <cstddef>
#include <string>
#include <vector>

namespace npf::edit::detail {

// Per-channel tables, channel after channel: value(c, cell) = v[c * cells + cell].
struct Tables {
    std::size_t channels = 0, cells = 0;
    std::vector<double> v;
    double* row(std::size_t c) { return v.data() + c * cells; }
    const double* row(std::size_t c) const { return v.data() + c * cells; }
};

// sum_k weights[c][k] basis[k] at every cell, not clamped (the model clamps after interpolating).
Tables expand(const SpectralBasis& basis, std::size_t channels);

// The uncompressed factors of `model` with D and G taken from `d` and `g` (on the grids given):
// what the converter's compression takes.
NpfFactors factors_of(const NpfModel& model, const Tables& d, int d_phi, const Tables& g, int g_phi);

// The model with D and G replaced by SVD compressions of `d` and `g` (on the grids given), the
// ranks chosen as `how` says from the input's (`like`). Everything else is copied from `model`.
NpfModel recompress(const NpfModel& model, const Tables& d, int d_phi, const Tables& g, int g_phi,
                    const NpfModel& like, Recompress how);

// Projected area of each channel of D tables on a (d_theta x d_phi) grid, cells clamped at 0.
std::vector<double> projected_areas(const Tables& d, int d_theta, int d_phi);

// A per-channel, reflectance-like quantity (albedo, a specular colour) moved from one channel set
// to another: equal sets are copied; spectral to spectral interpolates linearly (constant beyond
// the source's range, with a warning when the target reaches more than 5 nm past it); spectral
// to RGB takes the colour (linear sRGB under D65, docs/color.md), negative components clamped to
// 0 with a warning; RGB to spectral upsamples with the sigmoid of rgb_sigmoid.h (refined fit;
// colours above 1 through RgbUnboundedSpectrum). `what` names the quantity in warnings.
std::vector<double> convert_channels(const Channels& from, const std::vector<double>& values, const Channels& to,
                                     const std::string& what, EditRecord* record);

// The detail layer (docs/editing.md, "Edits and the detail layer") was fitted to the input's own
// lobe; an edit that reshapes the lobe or its Fresnel removes it, with a warning naming why.
// Nothing happens when the model has none.
void drop_detail(NpfModel& model, EditRecord* record, const std::string& why);

// "1.234" with up to `digits` significant digits.

void warn(EditRecord* record, const std::string& text);

}  // namespace npf::edit::detail
