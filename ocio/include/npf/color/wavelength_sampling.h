// Hero-wavelength spectral sampling (pbrt-v4 style) and the estimator that turns the sampled
// values into CIE XYZ under npf's colour convention.
//
// Wavelengths are drawn over 360..830 nm with density proportional to 1 / cosh^2(0.0072 (l - 538))
// (Radziszewski et al.'s visible-importance curve, as pbrt-v4's SampleVisibleWavelengths and
// Mitsuba 3's sample_rgb_spectrum use), normalised exactly on that range; the inverse CDF is
// analytic. One uniform number gives four stratified wavelengths: u, u + 1/4, u + 1/2, u + 3/4
// (mod 1), each marginally distributed with that density (pbrt-v4's SampleVisible).
//
// Estimator. With values v(l_k) at the four wavelengths,
//     XYZ_estimate = 1/4 sum_k w(l_k) v(l_k) / pdf(l_k)
// is unbiased for integral(w v) over 360..830 nm, where w depends on what the values are:
//  - SpectralUnits::RelativeToD65 (npf's convention, that of spectrum_to_xyz): v is what the
//    scene reflects of a D65 light, w = E_D65 cmf / integral(E_D65 ybar). A constant 1 gives
//    the D65 white with Y = 1 exactly (in expectation); any spectrum gives spectrum_to_xyz's
//    value to within the difference between its 1 nm sum and the integral (for the white:
//    5e-8 in X, 0 in Y, 1.3e-5 in Z).
//  - SpectralUnits::Radiance: v already includes the light's spectrum, with lights normalised
//    to unit luminance, w = cmf. This is pbrt-v4's convention: its lights divide their spectrum
//    by integral(ybar s) ("1 nit"; SpectrumToPhotometric) and its default cie1931 PixelSensor
//    sums cmf L / pdf with no further factor, whereas pbrt's SpectrumToXYZ divides by
//    CIE_Y_integral = 106.856895 (an equal-energy white at Y = 1). Mitsuba 3 likewise scales by
//    1 / 106.75 (MI_CIE_Y_NORMALIZATION). d65_unit_luminance() is such a light; radiance
//    v * d65_unit_luminance estimates the same XYZ as v RelativeToD65.
// The integrals use the CIE and D65 tables linearly interpolated (cie_1931, illuminant_d65).
#pragma once

#include <npf/color/spectrum.h>

#include <array>
#include <cstddef>

namespace npf::color {

inline constexpr double kVisibleMinNm = 360.0;
inline constexpr double kVisibleMaxNm = 830.0;

// Density (1/nm) of sample_visible_wavelength: 0 outside 360..830 nm.
double visible_wavelength_pdf(double lambda_nm);
// Its distribution function: 0 at 360 nm, 1 at 830 nm.
double visible_wavelength_cdf(double lambda_nm);
// Inverse of the distribution function, u in [0, 1] (clamped; NaN gives 360 nm).
double sample_visible_wavelength(double u);

inline constexpr int kHeroWavelengthCount = 4;

struct HeroWavelengths {
    std::array<double, kHeroWavelengthCount> lambda_nm;
    std::array<double, kHeroWavelengthCount> pdf;  // visible_wavelength_pdf of each
};

// The four stratified wavelengths for one uniform number u in [0, 1).
HeroWavelengths sample_hero_wavelengths(double u);

enum class SpectralUnits { RelativeToD65, Radiance };

// D65 scaled to unit luminance: E_D65(l) / integral(E_D65 ybar) over 360..830 nm (1/nm). A light
// with this spectrum, seen directly, has Y = 1.
double d65_unit_luminance(double lambda_nm);

// One sample's XYZ estimate (the formula above). Wavelengths with zero pdf contribute nothing.
Xyz hero_xyz_estimate(const HeroWavelengths& wavelengths, const std::array<double, kHeroWavelengthCount>& values,
                      SpectralUnits units = SpectralUnits::RelativeToD65);

// Averages hero_xyz_estimate over many samples (a pixel), with the standard error of the mean.
class HeroXyzAccumulator {
public:
    explicit HeroXyzAccumulator(SpectralUnits units = SpectralUnits::RelativeToD65) : m_units(units) {}

    void add(const HeroWavelengths& wavelengths, const std::array<double, kHeroWavelengthCount>& values);

    std::size_t count() const { return m_count; }
    Xyz mean() const { return m_mean; }  // zeros before the first sample
    // Standard error of mean() per channel (sample standard deviation / sqrt(count)); 0 with
    // fewer than two samples.
    Xyz standard_error() const;

private:
    SpectralUnits m_units;
    std::size_t m_count = 0;
    Xyz m_mean{0.0, 0.0, 0.0};
    Xyz m_m2{0.0, 0.0, 0.0};  // Welford's running sum of squared deviations
};

}  // namespace npf::color
