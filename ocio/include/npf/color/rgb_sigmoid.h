// Fast RGB to spectrum for textures and environment maps: Jakob & Hanika, "A Low-Dimensional
// Function Space for Efficient Spectral Upsampling" (Eurographics 2019), the method pbrt-v4
// implements (RGBToSpectrumTable, RGBUnboundedSpectrum, RGBIlluminantSpectrum).
//
// A reflectance is s(l) = S(c0 l^2 + c1 l + c2), l in nm, with S(x) = 1/2 + x / (2 sqrt(1 + x^2))
// a sigmoid onto (0, 1): smooth, bounded, three numbers per colour. The coefficients are fitted
// (Gauss-Newton on the CIELAB difference, as pbrt's rgb2spec_opt) so that the spectrum's colour
// under npf's convention (spectrum_to_xyz: under D65, 1 nm sums, then xyz_to_linear_srgb) is
// the linear sRGB colour. They are tabulated when npf is built, over a grid indexed by the
// largest component z and the other two divided by it (pbrt's layout and z spacing, 32 nodes
// per axis instead of pbrt's 64); a colour's coefficients are interpolated trilinearly.
//
// Accuracy (docs/color.md has the measurements): the table alone returns colours to about 1e-3
// (median 8e-4, 99th percentile 2.5e-3, up to 2.3e-2 near the white corner, where two
// components are close to 1). SigmoidFit::Refined continues Gauss-Newton from the table's
// coefficients and returns the colour to rounding wherever the sigmoid family reaches it: all of
// [0, 1]^3 but pure green and magenta (5.7e-4 off) and a thin sliver at the white corner (for
// example (1, 0.99, 1) or (0.975, 1, 0.97), up to 2.3e-2 off), which no spectrum of this family
// has. linear_srgb_to_spectrum (spectrum.h) stays the exact method for every colour.
#pragma once

#include <npf/color/spectrum.h>

#include <array>

namespace npf::color {

class RgbSigmoid {
public:
    // The zero spectrum (c2 = -infinity).
    RgbSigmoid();
    // s(l) = S(c0 l^2 + c1 l + c2); c2 may be +-infinity (the constants 1 and 0).
    RgbSigmoid(double c0, double c1, double c2);

    double operator()(double lambda_nm) const;
    // The largest value over 360..830 nm.
    double max_value() const;
    const std::array<double, 3>& coefficients() const { return m_c; }
    // The spectrum at every whole nanometre 360..830 (what spectrum_to_xyz integrates).
    SampledSpectrum tabulate() const;

private:
    std::array<double, 3> m_c;
};

enum class SigmoidFit {
    Table,    // trilinear lookup: about 0.15 us, colour to about 1e-3
    Refined,  // lookup, then Gauss-Newton to convergence: about 15 us, exact where reachable
};

// The reflectance for a linear sRGB colour in [0, 1]^3; components outside are clamped into
// it (use RgbUnboundedSpectrum for brighter colours). Greys give the constant spectrum (in both
// modes: flat, although a constant c has colour c (1.00016, 0.99998, 0.99976), see spectrum.h).
// Thread-safe; the first call loads the built-in table. Non-finite input
// throws npf::Error.
RgbSigmoid rgb_to_sigmoid(const Rgb& rgb, SigmoidFit fit = SigmoidFit::Table);

// Loads the built-in coefficient table now rather than at the first rgb_to_sigmoid call (a
// copy of 1.2 MB). Idempotent and thread-safe.
void prepare_rgb_sigmoid_table();

// Any non-negative colour, HDR included (pbrt-v4's RGBUnboundedSpectrum): scale = 2 max(rgb),
// s = rgb_to_sigmoid(rgb / scale), value scale * s(l). Linear in the colour's magnitude;
// negative components are taken as 0. For texture and environment-map values.
class RgbUnboundedSpectrum {
public:
    RgbUnboundedSpectrum() = default;  // zero
    explicit RgbUnboundedSpectrum(const Rgb& rgb, SigmoidFit fit = SigmoidFit::Table);
    double operator()(double lambda_nm) const { return m_scale * m_sigmoid(lambda_nm); }
    double scale() const { return m_scale; }
    const RgbSigmoid& sigmoid() const { return m_sigmoid; }

private:
    double m_scale = 0.0;
    RgbSigmoid m_sigmoid;
};

// An emitter's spectrum for a linear sRGB colour (pbrt-v4's RGBIlluminantSpectrum): the
// unbounded spectrum times D65 at unit luminance (d65_unit_luminance, wavelength_sampling.h),
// in SpectralUnits::Radiance. RGB (1, 1, 1) is D65 with Y = 1.
class RgbIlluminantSpectrum {
public:
    RgbIlluminantSpectrum() = default;  // zero
    explicit RgbIlluminantSpectrum(const Rgb& rgb, SigmoidFit fit = SigmoidFit::Table) : m_reflectance(rgb, fit) {}
    double operator()(double lambda_nm) const;
    const RgbUnboundedSpectrum& unbounded() const { return m_reflectance; }

private:
    RgbUnboundedSpectrum m_reflectance;
};

}  // namespace npf::color
