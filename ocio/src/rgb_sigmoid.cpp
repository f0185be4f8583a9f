// RgbSigmoid and the RGB -> sigmoid spectrum conversions built on the coefficient table.
#include "sigmoid_fit.h"

#include <npf/color/wavelength_sampling.h>
#include <npf/core/error.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace npf::color {

namespace {

// Refinement: to a Lab residual of 1e-7 (colour error ~1e-9), which Gauss-Newton reaches in two
// or three steps from the table's start where the colour is reachable at all.
constexpr double kRefineTolerance = 1e-14;
constexpr int kRefineIterations = 50;

double sigmoid(double p) {
    // Beyond 1e8 the value is within 3e-17 of its limit (and p * p would overflow further out).
    if (p > 1e8) return 1.0;
    if (p < -1e8) return 0.0;
    return 0.5 + 0.5 * p / std::sqrt(1.0 + p * p);
}

}  // namespace

namespace detail {

RgbSigmoid to_nanometres(const SigmoidCoefficients& c) {
    // p(x) with x = (l - l0) / span, expanded in powers of l.
    const double l0 = kSigmoidFirstNm, inv = 1.0 / kSigmoidSpanNm;
    const double a = c[0], b = c[1], k = c[2];
    return RgbSigmoid(a * inv * inv, b * inv - 2.0 * a * l0 * inv * inv, k - b * l0 * inv + a * l0 * l0 * inv * inv);
}

}  // namespace detail

RgbSigmoid::RgbSigmoid() : m_c{0.0, 0.0, -std::numeric_limits<double>::infinity()} {}

RgbSigmoid::RgbSigmoid(double c0, double c1, double c2) : m_c{c0, c1, c2} {
    if (!std::isfinite(c0) || !std::isfinite(c1) || std::isnan(c2))
        throw Error("RgbSigmoid", "coefficients must be finite (c2 may be infinite)");
}

double RgbSigmoid::operator()(double lambda_nm) const {
    if (std::isinf(m_c[2])) return m_c[2] > 0.0 ? 1.0 : 0.0;
    return sigmoid((m_c[0] * lambda_nm + m_c[1]) * lambda_nm + m_c[2]);
}

double RgbSigmoid::max_value() const {
    // S is increasing, so the largest value is at an end or at the polynomial's vertex.
    double m = std::max((*this)(kVisibleMinNm), (*this)(kVisibleMaxNm));
    if (m_c[0] != 0.0) {
        const double vertex = -m_c[1] / (2.0 * m_c[0]);
        if (vertex > kVisibleMinNm && vertex < kVisibleMaxNm) m = std::max(m, (*this)(vertex));
    }
    return m;
}

SampledSpectrum RgbSigmoid::tabulate() const {
    std::vector<double> wavelengths, values;
    for (int l = static_cast<int>(kVisibleMinNm); l <= static_cast<int>(kVisibleMaxNm); ++l) {
        wavelengths.push_back(l);
        values.push_back((*this)(l));
    }
    return SampledSpectrum(std::move(wavelengths), std::move(values));
}

RgbSigmoid rgb_to_sigmoid(const Rgb& rgb, SigmoidFit fit) {
    if (!std::isfinite(rgb[0]) || !std::isfinite(rgb[1]) || !std::isfinite(rgb[2]))
        throw Error("rgb_to_sigmoid", "non-finite colour");
    Rgb c{std::clamp(rgb[0], 0.0, 1.0), std::clamp(rgb[1], 0.0, 1.0), std::clamp(rgb[2], 0.0, 1.0)};
    if (c[0] == c[1] && c[1] == c[2]) {
        // Grey: the constant spectrum S(c2) = value (infinite at 0 and 1).
        const double v = c[0];
        const double inf = std::numeric_limits<double>::infinity();
        return RgbSigmoid(0.0, 0.0, v <= 0.0 ? -inf : v >= 1.0 ? inf : (v - 0.5) / std::sqrt(v * (1.0 - v)));
    }
    detail::SigmoidCoefficients coefficients = detail::sigmoid_table().lookup(c);
    if (fit == SigmoidFit::Refined)
        detail::fit_sigmoid(c, coefficients, detail::Quadrature::Exact, kRefineTolerance, kRefineIterations);
    return detail::to_nanometres(coefficients);
}

void prepare_rgb_sigmoid_table() { detail::sigmoid_table(); }

RgbUnboundedSpectrum::RgbUnboundedSpectrum(const Rgb& rgb, SigmoidFit fit) {
    if (!std::isfinite(rgb[0]) || !std::isfinite(rgb[1]) || !std::isfinite(rgb[2]))
        throw Error("RgbUnboundedSpectrum", "non-finite colour");
    const Rgb c{std::max(rgb[0], 0.0), std::max(rgb[1], 0.0), std::max(rgb[2], 0.0)};
    const double largest = std::max({c[0], c[1], c[2]});
    if (!(largest > 0.0)) return;  // black
    m_scale = 2.0 * largest;
    m_sigmoid = rgb_to_sigmoid({c[0] / m_scale, c[1] / m_scale, c[2] / m_scale}, fit);
}

double RgbIlluminantSpectrum::operator()(double lambda_nm) const {
    return m_reflectance(lambda_nm) * d65_unit_luminance(lambda_nm);
}

}  // namespace npf::color
