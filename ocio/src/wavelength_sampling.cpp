// The visible-wavelength density, hero-wavelength sets and the XYZ estimator.
#include <npf/color/wavelength_sampling.h>

#include <algorithm>
#include <cmath>

namespace npf::color {

namespace {

// pdf(l) = a / (S cosh^2(a (l - c))) on [360, 830]; its CDF is (tanh(a (l - c)) - t_lo) / S.
// pbrt-v4 rounds the resulting constants to floats (0.0039398042, 0.85691062, 1.82750197).
constexpr double kSlope = 0.0072;  // a, 1/nm
constexpr double kCentreNm = 538.0;  // c

struct Curve {
    double t_lo, t_hi, span;  // tanh at the two ends, S = t_hi - t_lo
};

const Curve& curve() {
    static const Curve k = [] {
        Curve c{};
        c.t_lo = std::tanh(kSlope * (kVisibleMinNm - kCentreNm));
        c.t_hi = std::tanh(kSlope * (kVisibleMaxNm - kCentreNm));
        c.span = c.t_hi - c.t_lo;
        return c;
    }();
    return k;
}

// integral of E_D65 ybar over 360..830 nm, exactly for the linearly interpolated tables: both
// are linear on every 1 nm interval (the D65 table's 5 nm knots fall on whole nanometres), so
// each interval's integral of the product is (2 a0 b0 + a0 b1 + a1 b0 + 2 a1 b1) / 6.
double d65_luminance_integral() {
    static const double total = [] {
        double sum = 0.0;
        for (int l = static_cast<int>(kVisibleMinNm); l < static_cast<int>(kVisibleMaxNm); ++l) {
            const double a0 = illuminant_d65(l), a1 = illuminant_d65(l + 1);
            const double b0 = cie_1931(l)[1], b1 = cie_1931(l + 1)[1];
            sum += (2.0 * a0 * b0 + a0 * b1 + a1 * b0 + 2.0 * a1 * b1) / 6.0;
        }
        return sum;
    }();
    return total;
}

}  // namespace

double visible_wavelength_pdf(double lambda_nm) {
    if (!(lambda_nm >= kVisibleMinNm && lambda_nm <= kVisibleMaxNm)) return 0.0;
    const double ch = std::cosh(kSlope * (lambda_nm - kCentreNm));
    return kSlope / (curve().span * ch * ch);
}

double visible_wavelength_cdf(double lambda_nm) {
    if (!(lambda_nm > kVisibleMinNm)) return 0.0;
    if (lambda_nm >= kVisibleMaxNm) return 1.0;
    const Curve& k = curve();
    return (std::tanh(kSlope * (lambda_nm - kCentreNm)) - k.t_lo) / k.span;
}

double sample_visible_wavelength(double u) {
    if (!(u > 0.0)) return kVisibleMinNm;
    if (u >= 1.0) return kVisibleMaxNm;
    const Curve& k = curve();
    const double lambda = kCentreNm + std::atanh(k.t_lo + k.span * u) / kSlope;
    return std::clamp(lambda, kVisibleMinNm, kVisibleMaxNm);  // rounding at the ends
}

HeroWavelengths sample_hero_wavelengths(double u) {
    HeroWavelengths h{};
    for (int k = 0; k < kHeroWavelengthCount; ++k) {
        double up = u + static_cast<double>(k) / kHeroWavelengthCount;
        if (up >= 1.0) up -= 1.0;
        h.lambda_nm[k] = sample_visible_wavelength(up);
        h.pdf[k] = visible_wavelength_pdf(h.lambda_nm[k]);
    }
    return h;
}

double d65_unit_luminance(double lambda_nm) { return illuminant_d65(lambda_nm) / d65_luminance_integral(); }

Xyz hero_xyz_estimate(const HeroWavelengths& wavelengths, const std::array<double, kHeroWavelengthCount>& values,
                      SpectralUnits units) {
    Xyz xyz{0.0, 0.0, 0.0};
    for (int k = 0; k < kHeroWavelengthCount; ++k) {
        const double pdf = wavelengths.pdf[k];
        if (!(pdf > 0.0)) continue;
        const double lambda = wavelengths.lambda_nm[k];
        double weight = values[k] / (pdf * kHeroWavelengthCount);
        if (units == SpectralUnits::RelativeToD65) weight *= d65_unit_luminance(lambda);
        const Xyz cmf = cie_1931(lambda);
        for (int c = 0; c < 3; ++c) xyz[c] += weight * cmf[c];
    }
    return xyz;
}

void HeroXyzAccumulator::add(const HeroWavelengths& wavelengths,
                             const std::array<double, kHeroWavelengthCount>& values) {
    const Xyz x = hero_xyz_estimate(wavelengths, values, m_units);
    ++m_count;
    for (int c = 0; c < 3; ++c) {
        const double delta = x[c] - m_mean[c];
        m_mean[c] += delta / static_cast<double>(m_count);
        m_m2[c] += delta * (x[c] - m_mean[c]);
    }
}

Xyz HeroXyzAccumulator::standard_error() const {
    Xyz se{0.0, 0.0, 0.0};
    if (m_count < 2) return se;
    const double n = static_cast<double>(m_count);
    for (int c = 0; c < 3; ++c) se[c] = std::sqrt(m_m2[c] / (n - 1.0) / n);
    return se;
}

}  // namespace npf::color
