// Tests of hero-wavelength sampling and the XYZ estimator (npf/color/wavelength_sampling.h).
//
// Reference numbers: pbrt-v4's float constants (src/pbrt/util/sampling.h: pdf 0.0039398042 /
// cosh^2(0.0072 (l - 538)), sample 538 - 138.888889 atanh(0.85691062 - 1.82750197 u)); the CIE
// 015:2018 chromaticity of D65 for the 1931 observer, x = 0.31272, y = 0.32903.
#include <npf/color/spectrum.h>
#include <npf/color/wavelength_sampling.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <vector>

namespace {

using namespace npf::color;

// Deterministic uniforms in [0, 1): mt19937_64 is fully specified, the conversion is ours.
class Uniforms {
public:
    explicit Uniforms(std::uint64_t seed) : m_rng(seed) {}
    double next() { return static_cast<double>(m_rng() >> 11) * 0x1.0p-53; }

private:
    std::mt19937_64 m_rng;
};

// Composite Simpson over [a, b] with n (even) intervals.
double simpson(const std::function<double(double)>& f, double a, double b, int n) {
    const double h = (b - a) / n;
    double sum = f(a) + f(b);
    for (int i = 1; i < n; ++i) sum += f(a + i * h) * (i % 2 ? 4.0 : 2.0);
    return sum * h / 3.0;
}

// The estimator's mean after `n` hero samples of `spectrum` (values relative to D65).
HeroXyzAccumulator estimate(const std::function<double(double)>& spectrum, int n, std::uint64_t seed,
                            SpectralUnits units = SpectralUnits::RelativeToD65) {
    HeroXyzAccumulator acc(units);
    Uniforms u(seed);
    for (int i = 0; i < n; ++i) {
        const HeroWavelengths h = sample_hero_wavelengths(u.next());
        std::array<double, kHeroWavelengthCount> v{};
        for (int k = 0; k < kHeroWavelengthCount; ++k) v[k] = spectrum(h.lambda_nm[k]);
        acc.add(h, v);
    }
    return acc;
}

SampledSpectrum tabulate_1nm(const std::function<double(double)>& f) {
    std::vector<double> l, v;
    for (int i = 360; i <= 830; ++i) {
        l.push_back(i);
        v.push_back(f(i));
    }
    return SampledSpectrum(l, v);
}

// The Monte Carlo mean agrees with `reference` within `sigmas` standard errors, plus `bias` for
// the difference between spectrum_to_xyz's 1 nm sums and the integral.
void expect_within_standard_errors(const HeroXyzAccumulator& acc, const Xyz& reference, double sigmas, double bias) {
    const Xyz mean = acc.mean(), se = acc.standard_error();
    for (int c = 0; c < 3; ++c) {
        EXPECT_GT(se[c], 0.0);
        EXPECT_NEAR(mean[c], reference[c], sigmas * se[c] + bias)
            << "channel " << c << ", standard error " << se[c] << ", off by " << (mean[c] - reference[c]) / se[c]
            << " standard errors";
    }
}

TEST(WavelengthSampling, PdfIntegratesToOne) {
    EXPECT_NEAR(simpson(visible_wavelength_pdf, kVisibleMinNm, kVisibleMaxNm, 47000), 1.0, 1e-10);
    EXPECT_EQ(visible_wavelength_pdf(359.999), 0.0);
    EXPECT_EQ(visible_wavelength_pdf(830.001), 0.0);
    EXPECT_EQ(visible_wavelength_pdf(std::nan("")), 0.0);
    EXPECT_GT(visible_wavelength_pdf(360.0), 0.0);
}

TEST(WavelengthSampling, MatchesPbrtV4Constants) {
    // pbrt rounds its constants to floats; ours are exact, so they agree to float precision.
    EXPECT_NEAR(visible_wavelength_pdf(538.0), 0.0039398042, 2e-10);
    for (double l : {360.0, 400.0, 555.0, 700.0, 830.0})
        EXPECT_NEAR(visible_wavelength_pdf(l), 0.0039398042 / std::pow(std::cosh(0.0072 * (l - 538.0)), 2), 1e-9);
    for (double u : {0.001, 0.1, 0.25, 0.5, 0.75, 0.9, 0.999})
        EXPECT_NEAR(sample_visible_wavelength(u), 538.0 - 138.888889 * std::atanh(0.85691062 - 1.82750197 * u), 1e-4)
            << u;
}

TEST(WavelengthSampling, InverseCdfIsExact) {
    EXPECT_EQ(sample_visible_wavelength(0.0), 360.0);
    EXPECT_EQ(sample_visible_wavelength(1.0), 830.0);
    EXPECT_EQ(sample_visible_wavelength(-1.0), 360.0);
    EXPECT_EQ(sample_visible_wavelength(std::nan("")), 360.0);
    EXPECT_EQ(visible_wavelength_cdf(360.0), 0.0);
    EXPECT_EQ(visible_wavelength_cdf(830.0), 1.0);
    for (int i = 1; i < 1000; ++i) {
        const double u = i / 1000.0;
        const double l = sample_visible_wavelength(u);
        EXPECT_NEAR(visible_wavelength_cdf(l), u, 1e-12);
        // The pdf is the CDF's derivative.
        const double h = 1e-4;
        EXPECT_NEAR((visible_wavelength_cdf(l + h) - visible_wavelength_cdf(l - h)) / (2 * h),
                    visible_wavelength_pdf(l), 1e-9);
    }
}

TEST(WavelengthSampling, HeroSetIsStratifiedRotation) {
    for (double u : {0.0, 0.1, 0.3, 0.74, 0.75, 0.999}) {
        const HeroWavelengths h = sample_hero_wavelengths(u);
        for (int k = 0; k < kHeroWavelengthCount; ++k) {
            const double shifted = std::fmod(u + k / 4.0, 1.0);
            EXPECT_DOUBLE_EQ(h.lambda_nm[k], sample_visible_wavelength(shifted));
            EXPECT_DOUBLE_EQ(h.pdf[k], visible_wavelength_pdf(h.lambda_nm[k]));
        }
    }
    // Each of the four wavelengths has the visible density: a histogram of 10 nm bins matches
    // the CDF within 5 standard deviations per bin.
    const int n = 50000, bins = 47;
    std::vector<int> counts(bins, 0);
    Uniforms u(11);
    for (int i = 0; i < n; ++i)
        for (double l : sample_hero_wavelengths(u.next()).lambda_nm) ++counts[std::min(bins - 1, static_cast<int>((l - 360.0) / 10.0))];
    for (int b = 0; b < bins; ++b) {
        const double p = visible_wavelength_cdf(370.0 + 10.0 * b) - visible_wavelength_cdf(360.0 + 10.0 * b);
        const double expected = 4.0 * n * p, sd = std::sqrt(4.0 * n * p * (1 - p));
        EXPECT_NEAR(counts[b], expected, 5 * sd + 1) << "bin " << b;
    }
}

TEST(WavelengthSampling, UnitLuminanceD65) {
    const double y = simpson([](double l) { return d65_unit_luminance(l) * cie_1931(l)[1]; }, 360.0, 830.0, 4700);
    EXPECT_NEAR(y, 1.0, 1e-6);
}

TEST(WavelengthSampling, ConstantOneConvergesToTheD65White) {
    const HeroXyzAccumulator acc = estimate([](double) { return 1.0; }, 100000, 1);
    EXPECT_EQ(acc.count(), 100000u);
    expect_within_standard_errors(acc, spectrum_to_xyz(SampledSpectrum::constant(1.0)), 4.0, 2e-5);
    EXPECT_LT(acc.standard_error()[1], 2e-3);  // importance sampling keeps the white cheap
    // The white itself: CIE 015's chromaticity of D65 (1931 observer), Y = 1.
    const Xyz w = spectrum_to_xyz(SampledSpectrum::constant(1.0));
    EXPECT_NEAR(w[1], 1.0, 1e-12);
    EXPECT_NEAR(w[0] / (w[0] + w[1] + w[2]), 0.31272, 1e-5);
    EXPECT_NEAR(w[1] / (w[0] + w[1] + w[2]), 0.32903, 1e-5);
}

TEST(WavelengthSampling, SmoothSpectrumConvergesToSpectrumToXyz) {
    const auto smooth = [](double l) { return 0.5 + 0.4 * std::sin((l - 360.0) / 60.0); };
    const HeroXyzAccumulator acc = estimate(smooth, 100000, 2);
    expect_within_standard_errors(acc, spectrum_to_xyz(tabulate_1nm(smooth)), 4.0, 2e-5);
    // Radiance units: the same values times a unit-luminance D65 light give the same estimate.
    const HeroXyzAccumulator radiance =
        estimate([&](double l) { return smooth(l) * d65_unit_luminance(l); }, 100000, 2, SpectralUnits::Radiance);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(radiance.mean()[c], acc.mean()[c], 1e-12);
}

// A box spectrum, 1 on 500..600 nm and 0 elsewhere: its Y by hand from the CIE and D65 tables
// (Simpson on 0.01 nm steps of the interpolated tables, independently of npf's integration).
TEST(WavelengthSampling, BoxSpectrumYByHand) {
    const auto e_ybar = [](double l) { return illuminant_d65(l) * cie_1931(l)[1]; };
    const double by_hand = simpson(e_ybar, 500.0, 600.0, 10000) / simpson(e_ybar, 360.0, 830.0, 47000);
    // The same from the raw 1 nm CIE and 5 nm D65 numbers by the trapezoid rule (a short script
    // over ocio/src/cie_tables.cpp): 0.770865.
    EXPECT_NEAR(by_hand, 0.770865, 2e-6);
    const HeroXyzAccumulator acc = estimate([](double l) { return l >= 500.0 && l <= 600.0 ? 1.0 : 0.0; }, 100000, 3);
    EXPECT_NEAR(acc.mean()[1], by_hand, 4.0 * acc.standard_error()[1]);
}

TEST(WavelengthSampling, StandardErrorShrinksAsExpected) {
    const auto f = [](double l) { return l < 550.0 ? 0.2 : 0.8; };
    const HeroXyzAccumulator small = estimate(f, 2500, 4), large = estimate(f, 40000, 5);
    const double ratio = small.standard_error()[1] / large.standard_error()[1];
    EXPECT_NEAR(ratio, 4.0, 0.4);  // sqrt(40000 / 2500)
    EXPECT_EQ(HeroXyzAccumulator().standard_error()[1], 0.0);
    EXPECT_EQ(HeroXyzAccumulator().mean()[1], 0.0);
}

}  // namespace
