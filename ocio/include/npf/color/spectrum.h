// Spectra: tabulated spectra and their files, the CIE 1931 2-degree observer, spectrum to XYZ
// and to linear sRGB, and sRGB to a smooth reflectance spectrum.
//
// Colour conventions (fixed project-wide):
//  - Spectral values are reflectance-like (BRDF values, albedos). Their colour is taken under
//    illuminant D65, normalised so that a constant spectrum 1 has CIE Y = 1 and linear sRGB
//    (1, 1, 1): XYZ = integral(S E_D65 cmf) / integral(E_D65 ybar).
//  - RGB means linear sRGB (Rec. 709 primaries, D65 white), as in the RGL database files.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace npf::color {

// A spectrum tabulated at ascending wavelengths (nm): linear between samples, constant
// outside them (the RGL readers' rule).
class SampledSpectrum {
public:
    SampledSpectrum() = default;
    // Throws npf::Error (source "spectrum") for empty, unsorted or non-finite input, and for
    // sizes that differ. Wavelengths must be strictly ascending (no repeats).
    SampledSpectrum(std::vector<double> wavelengths_nm, std::vector<double> values);
    // One sample (at 560 nm), hence `value` at every wavelength.
    static SampledSpectrum constant(double value);

    // 0 for a default-constructed (empty) spectrum.
    double operator()(double lambda_nm) const;
    std::vector<double> sample(const std::vector<float>& wavelengths_nm) const;
    const std::vector<double>& wavelengths() const { return m_wavelengths; }
    const std::vector<double>& values() const { return m_values; }
    bool empty() const { return m_values.empty(); }

private:
    std::vector<double> m_wavelengths, m_values;
};

// Reads a two-column text file (wavelength in nm, value); '#' starts a comment, blank lines
// are skipped; the rows must be in ascending wavelength. Throws npf::Error naming the file and
// line for anything else (the format of ../shared/data/ior/*.spd): a missing file, a
// directory, a row without exactly two numbers, NaN or infinity, wavelengths not strictly
// ascending, no rows at all.
SampledSpectrum read_spd(const std::string& path);

using Xyz = std::array<double, 3>;
using Rgb = std::array<double, 3>;

// CIE 1931 2-degree colour matching functions (x-bar, y-bar, z-bar) at `lambda_nm`, linearly
// interpolated from the 1 nm table over 360..830 nm, zero outside.
Xyz cie_1931(double lambda_nm);
// CIE standard illuminant D65, relative spectral power (100 at 560 nm), 300..830 nm, zero outside.
double illuminant_d65(double lambda_nm);

// XYZ of a spectrum under D65 (normalised as above), integrated finely (1 nm) over 360..830 nm.
Xyz spectrum_to_xyz(const SampledSpectrum& s);

// Weights that turn values sampled at `wavelengths_nm` (any ascending list) into XYZ or linear
// sRGB under the convention above: sum_k w[c][k] v[k]. The samples are treated as a piecewise-
// linear spectrum (constant beyond the ends), so a constant spectrum 1 gives Y = 1 and RGB
// (1, 1, 1) to about 1e-3 for any list that covers the visible range; a list that covers only
// part of it gives the colour of the spectrum extended constantly. For a strictly ascending
// list the sum equals spectrum_to_xyz(SampledSpectrum(wavelengths, values)) to rounding;
// repeated wavelengths are allowed (a jump there); an empty, descending or non-finite list
// throws npf::Error (source "wavelength list").
// With the tabulated D65, a constant 1 gives linear sRGB (1.00016, 0.99998, 0.99976): the
// standard matrix's white (x, y = 0.3127, 0.3290) is not exactly the table's; not renormalised.
std::array<std::vector<double>, 3> xyz_weights(const std::vector<float>& wavelengths_nm);
std::array<std::vector<double>, 3> linear_srgb_weights(const std::vector<float>& wavelengths_nm);
// Luminance (CIE Y) weights alone: the middle row of xyz_weights.
std::vector<double> luminance_weights(const std::vector<float>& wavelengths_nm);

Rgb xyz_to_linear_srgb(const Xyz& xyz);
Xyz linear_srgb_to_xyz(const Rgb& rgb);
// Luminance of a linear sRGB colour (Rec. 709 weights).
double linear_srgb_luminance(const Rgb& rgb);
// The sRGB transfer function and its inverse (encoded 0..1 <-> linear).
double srgb_to_linear(double encoded);
double linear_to_srgb(double linear);

// A smooth reflectance spectrum whose colour (convention above) is the linear sRGB colour
// `rgb`: the spectrum on 360..830 nm (5 nm) that minimises the squared second differences
// subject to matching XYZ exactly, with values kept in [0, 1] where the colour allows (an
// active-set refinement). Round trip: spectrum_to_xyz -> xyz_to_linear_srgb returns `rgb`
// to 1e-3 for colours inside the sRGB gamut with components in [0, 1] (in fact to rounding,
// for any finite colour). Where no spectrum within [0, 1] has the colour (components above 1,
// some colours outside the gamut, and white (1, 1, 1) itself, see above) the bounds give
// way, first to values >= 0 only, then to none; the colour match is kept. Non-finite input
// throws npf::Error.
SampledSpectrum linear_srgb_to_spectrum(const Rgb& rgb);
// The same for sRGB-encoded components (decoded first).
SampledSpectrum srgb_to_spectrum(double r, double g, double b);

}  // namespace npf::color
