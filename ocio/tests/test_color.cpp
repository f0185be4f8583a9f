// Tests of npf_color: the CIE tables, SampledSpectrum and .spd files, spectrum -> XYZ weights,
// XYZ <-> linear sRGB, the sRGB transfer functions and RGB -> smooth spectrum.
//
// Reference numbers not computed by npf come from the CIE tables themselves and from
// colour-science 0.4.7 (colour.sd_to_XYZ, method 'Integration', D65, CIE 1931 2-degree).
#include <npf/color/spectrum.h>
#include <npf/core/error.h>

#include <synthetic_rgl.h>

#include "error_of.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace npf::color;

std::vector<float> grid(float first, float last, float step) {
    std::vector<float> out;
    for (int i = 0;; ++i) {
        const float w = first + step * static_cast<float>(i);
        if (w > last + 1e-3f) break;
        out.push_back(w);
    }
    return out;
}

Xyz apply_weights(const std::array<std::vector<double>, 3>& w, const std::vector<double>& v) {
    Xyz out{0.0, 0.0, 0.0};
    for (int c = 0; c < 3; ++c)
        for (std::size_t k = 0; k < v.size(); ++k) out[c] += w[c][k] * v[k];
    return out;
}

double max_abs_diff(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

double max_second_difference(const SampledSpectrum& s) {
    const auto& v = s.values();
    double m = 0.0;
    for (std::size_t i = 1; i + 1 < v.size(); ++i)
        m = std::max(m, std::abs(v[i - 1] - 2.0 * v[i] + v[i + 1]));
    return m;
}

using npf::testing::error_of;

// ---------------------------------------------------------------------------------------------
// CIE tables

TEST(ColorTables, CmfKnownValues) {
    // CIE 015:2018, 1931 2-degree observer at 1 nm.
    EXPECT_DOUBLE_EQ(cie_1931(555.0)[1], 1.0);
    EXPECT_DOUBLE_EQ(cie_1931(600.0)[0], 1.0622);
    EXPECT_DOUBLE_EQ(cie_1931(600.0)[1], 0.631);
    EXPECT_DOUBLE_EQ(cie_1931(600.0)[2], 0.0008);
    EXPECT_DOUBLE_EQ(cie_1931(446.0)[2], 1.7829682);  // z-bar's maximum
    EXPECT_DOUBLE_EQ(cie_1931(360.0)[0], 0.0001299);
    // y-bar peaks at 555 nm.
    for (int l = 360; l <= 830; ++l) EXPECT_LE(cie_1931(l)[1], 1.0) << l;
    EXPECT_LT(cie_1931(554.0)[1], 1.0);
    EXPECT_LT(cie_1931(556.0)[1], 1.0);
}

TEST(ColorTables, CmfInterpolatesAndIsZeroOutside) {
    const Xyz a = cie_1931(600.0), b = cie_1931(601.0), mid = cie_1931(600.25);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mid[c], 0.75 * a[c] + 0.25 * b[c], 1e-15);
    for (double l : {359.99, 830.01, 100.0, 2000.0, std::numeric_limits<double>::quiet_NaN()}) {
        const Xyz v = cie_1931(l);
        EXPECT_EQ(v[0], 0.0);
        EXPECT_EQ(v[1], 0.0);
        EXPECT_EQ(v[2], 0.0);
    }
    EXPECT_GT(cie_1931(830.0)[0], 0.0);
}

TEST(ColorTables, D65KnownValues) {
    EXPECT_DOUBLE_EQ(illuminant_d65(560.0), 100.0);
    EXPECT_DOUBLE_EQ(illuminant_d65(300.0), 0.0341);
    EXPECT_DOUBLE_EQ(illuminant_d65(600.0), 90.0062);
    EXPECT_DOUBLE_EQ(illuminant_d65(780.0), 63.3828);
    EXPECT_DOUBLE_EQ(illuminant_d65(830.0), 60.3125);
    EXPECT_NEAR(illuminant_d65(562.5), 0.5 * (100.0 + 98.1671), 1e-12);
    EXPECT_EQ(illuminant_d65(299.9), 0.0);
    EXPECT_EQ(illuminant_d65(830.1), 0.0);
}

// ---------------------------------------------------------------------------------------------
// SampledSpectrum and .spd files

TEST(ColorSpectrum, InterpolatesLinearlyAndExtendsConstantly) {
    const SampledSpectrum s({400.0, 500.0, 700.0}, {1.0, 3.0, -1.0});
    EXPECT_DOUBLE_EQ(s(400.0), 1.0);
    EXPECT_DOUBLE_EQ(s(450.0), 2.0);
    EXPECT_DOUBLE_EQ(s(600.0), 1.0);
    EXPECT_DOUBLE_EQ(s(300.0), 1.0);
    EXPECT_DOUBLE_EQ(s(900.0), -1.0);
    const auto v = s.sample({350.f, 475.f, 700.f});
    ASSERT_EQ(v.size(), 3u);
    EXPECT_DOUBLE_EQ(v[0], 1.0);
    EXPECT_DOUBLE_EQ(v[1], 2.5);
    EXPECT_DOUBLE_EQ(v[2], -1.0);

    const SampledSpectrum c = SampledSpectrum::constant(0.25);
    for (double l : {200.0, 555.0, 1000.0}) EXPECT_EQ(c(l), 0.25);
    EXPECT_FALSE(c.empty());
    EXPECT_TRUE(SampledSpectrum().empty());
    EXPECT_EQ(SampledSpectrum()(500.0), 0.0);
}

TEST(ColorSpectrum, RejectsBadInput) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NE(error_of([] { SampledSpectrum({}, {}); }).find("no samples"), std::string::npos);
    EXPECT_NE(error_of([] { SampledSpectrum({400.0, 500.0}, {1.0}); }).find("2 wavelengths but 1"),
              std::string::npos);
    EXPECT_NE(error_of([] { SampledSpectrum({500.0, 400.0}, {1.0, 2.0}); }).find("ascending"),
              std::string::npos);
    EXPECT_NE(error_of([] { SampledSpectrum({500.0, 500.0}, {1.0, 2.0}); }).find("ascending"),
              std::string::npos);
    EXPECT_NE(error_of([&] { SampledSpectrum({400.0, 500.0}, {1.0, nan}); }).find("non-finite"),
              std::string::npos);
    EXPECT_NE(error_of([&] { SampledSpectrum({nan}, {1.0}); }).find("non-finite"), std::string::npos);
    EXPECT_NE(error_of([&] { SampledSpectrum::constant(nan); }).find("spectrum"), std::string::npos);
}

class ColorSpd : public ::testing::Test {
protected:
    std::string write(const std::string& name, const std::string& text) {
        const std::string path = (fs::path(m_dir) / name).string();
        std::ofstream(path, std::ios::binary) << text;
        return path;
    }
    std::string m_dir = npf::testing::temporary_folder("color_spd");
};

TEST_F(ColorSpd, ReadsCommentsBlankLinesAndCrlf) {
    const std::string path = write("good.spd",
                                   "# a comment\r\n"
                                   "\r\n"
                                   "400 0.5   # trailing comment\r\n"
                                   "\t500\t1e-1\r\n"
                                   "  600.5  +2.0\n"
                                   "# end\n");
    const SampledSpectrum s = read_spd(path);
    ASSERT_EQ(s.values().size(), 3u);
    EXPECT_EQ(s.wavelengths()[0], 400.0);
    EXPECT_EQ(s.wavelengths()[2], 600.5);
    EXPECT_EQ(s.values()[0], 0.5);
    EXPECT_EQ(s.values()[1], 0.1);
    EXPECT_EQ(s.values()[2], 2.0);
    EXPECT_EQ(read_spd(write("one.spd", "550 3\n")).values().size(), 1u);
}

TEST_F(ColorSpd, ReadsSharedCopperIor) {
    const std::string path = npf::testing::shared_data_file("ior/Cu.eta.spd");
    if (path.empty()) GTEST_SKIP() << "../shared/data/ior/Cu.eta.spd not found";
    const SampledSpectrum s = read_spd(path);
    ASSERT_EQ(s.values().size(), 55u);
    EXPECT_DOUBLE_EQ(s.wavelengths().front(), 302.400421);
    EXPECT_DOUBLE_EQ(s.values().front(), 1.38);
    EXPECT_DOUBLE_EQ(s.wavelengths().back(), 885.601257);
    EXPECT_DOUBLE_EQ(s.values().back(), 0.3);
    // Copper's eta: about 1.1 in the blue, 0.2..0.3 in the red; constant outside the table.
    EXPECT_GT(s(450.0), 1.0);
    EXPECT_LT(s(650.0), 0.4);
    EXPECT_EQ(s(1000.0), 0.3);
}

TEST_F(ColorSpd, RejectsBadFiles) {
    const auto message = [&](const std::string& name, const std::string& text) {
        const std::string path = write(name, text);
        const std::string m = error_of([&] { read_spd(path); });
        EXPECT_NE(m.find(path), std::string::npos) << m;  // names the file
        return m;
    };
    std::string m = message("word.spd", "# header\n400 1\n500 abc\n");
    EXPECT_NE(m.find("line 3"), std::string::npos) << m;
    EXPECT_NE(m.find("'abc'"), std::string::npos) << m;
    m = message("unit.spd", "400nm 1\n");
    EXPECT_NE(m.find("line 1"), std::string::npos) << m;
    m = message("descending.spd", "400 1\n500 1\n450 1\n");
    EXPECT_NE(m.find("line 3"), std::string::npos) << m;
    EXPECT_NE(m.find("ascending"), std::string::npos) << m;
    m = message("repeat.spd", "400 1\n400 2\n");
    EXPECT_NE(m.find("ascending"), std::string::npos) << m;
    m = message("empty.spd", "");
    EXPECT_NE(m.find("no data rows"), std::string::npos) << m;
    m = message("comments.spd", "# nothing\n\n   \n");
    EXPECT_NE(m.find("no data rows"), std::string::npos) << m;
    m = message("nan.spd", "400 1\n500 nan\n");
    EXPECT_NE(m.find("line 2"), std::string::npos) << m;
    EXPECT_NE(m.find("non-finite"), std::string::npos) << m;
    m = message("inf.spd", "inf 1\n");
    EXPECT_NE(m.find("non-finite"), std::string::npos) << m;
    m = message("three.spd", "400 1 2\n");
    EXPECT_NE(m.find("expected 2 numbers"), std::string::npos) << m;
    m = message("one_column.spd", "400 1\n500\n");
    EXPECT_NE(m.find("line 2"), std::string::npos) << m;

    const std::string missing = (fs::path(m_dir) / "missing.spd").string();
    m = error_of([&] { read_spd(missing); });
    EXPECT_NE(m.find(missing), std::string::npos) << m;
    EXPECT_NE(m.find("not found"), std::string::npos) << m;
    m = error_of([&] { read_spd(m_dir); });
    EXPECT_NE(m.find("directory"), std::string::npos) << m;
}

// ---------------------------------------------------------------------------------------------
// Spectrum -> XYZ / linear sRGB

TEST(ColorXyz, ConstantSpectrumIsTheWhite) {
    const Xyz w = spectrum_to_xyz(SampledSpectrum::constant(1.0));
    EXPECT_NEAR(w[1], 1.0, 1e-12);
    // The D65 white point of the 2-degree observer at 1 nm: 95.047, 100, 108.883 (CIE 015);
    // colour-science gives 0.95047076, 1, 1.08882842.
    EXPECT_NEAR(w[0], 0.95047076, 1e-6);
    EXPECT_NEAR(w[2], 1.08882842, 1e-6);
    const Xyz half = spectrum_to_xyz(SampledSpectrum::constant(0.5));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(half[c], 0.5 * w[c], 1e-12);
    const Xyz zero = spectrum_to_xyz(SampledSpectrum());
    EXPECT_EQ(zero[0] + zero[1] + zero[2], 0.0);
}

TEST(ColorXyz, ConstantSpectrumGivesWhiteForAnyList) {
    const Xyz white = spectrum_to_xyz(SampledSpectrum::constant(1.0));
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(250.f, 1000.f);
    std::vector<std::vector<float>> lists = {{560.f}, {300.f}, grid(400.f, 700.f, 50.f),
                                             grid(360.f, 1000.f, 3.3f), {500.f, 500.f, 600.f}};
    for (int r = 0; r < 20; ++r) {
        std::vector<float> l(1 + rng() % 40);
        for (float& w : l) w = u(rng);
        std::sort(l.begin(), l.end());
        lists.push_back(l);
    }
    for (const auto& list : lists) {
        const auto w = xyz_weights(list);
        const Xyz xyz = apply_weights(w, std::vector<double>(list.size(), 1.0));
        EXPECT_NEAR(xyz[1], 1.0, 1e-12) << list.size();
        EXPECT_LT(max_abs_diff(xyz, white), 1e-12) << list.size();
        const Rgb rgb = apply_weights(linear_srgb_weights(list), std::vector<double>(list.size(), 1.0));
        // The standard matrix's white differs from the tabulated D65's: 1.6e-4, -2.4e-5, -2.4e-4.
        EXPECT_LT(max_abs_diff(rgb, {1.0, 1.0, 1.0}), 3e-4) << list.size();
        EXPECT_NEAR(rgb[2], 0.99975847, 1e-6);
        const auto y = luminance_weights(list);
        ASSERT_EQ(y.size(), list.size());
        for (std::size_t k = 0; k < y.size(); ++k) EXPECT_EQ(y[k], w[1][k]);
    }
    // A single sample carries the whole integral.
    const auto single = xyz_weights({700.f});
    EXPECT_NEAR(single[0][0], white[0], 1e-12);
    EXPECT_NEAR(single[1][0], 1.0, 1e-12);
    EXPECT_NEAR(single[2][0], white[2], 1e-12);
}

TEST(ColorXyz, WeightsMatchTheSampledSpectrum) {
    // sum w v equals spectrum_to_xyz of the same samples read as a SampledSpectrum, including
    // lists that cover only part of 360..830 nm (constant extension) or reach beyond it.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (const auto& list : {grid(400.f, 700.f, 50.f), grid(500.f, 600.f, 10.f), grid(300.f, 900.f, 7.5f),
                             std::vector<float>{450.f, 451.5f, 620.f}}) {
        std::vector<double> v(list.size());
        for (double& x : v) x = u(rng);
        const SampledSpectrum s(std::vector<double>(list.begin(), list.end()), v);
        const Xyz expected = spectrum_to_xyz(s);
        EXPECT_LT(max_abs_diff(apply_weights(xyz_weights(list), v), expected), 1e-12);
        EXPECT_LT(max_abs_diff(apply_weights(linear_srgb_weights(list), v), xyz_to_linear_srgb(expected)),
                  1e-12);
    }
}

TEST(ColorXyz, BoxSpectrumByHandAndByIndependentIntegration) {
    // 1 on 500..600 nm, 0 elsewhere. Under the 1 nm rule, the whole nanometres 500..600 count.
    const SampledSpectrum box({499.5, 500.0, 600.0, 600.5}, {0.0, 1.0, 1.0, 0.0});
    const Xyz xyz = spectrum_to_xyz(box);

    // By hand: the same 1 nm sums from the public tables.
    double num = 0.0, den = 0.0;
    for (int l = 360; l <= 830; ++l) {
        const double ey = illuminant_d65(l) * cie_1931(l)[1];
        den += ey;
        if (l >= 500 && l <= 600) num += ey;
    }
    EXPECT_NEAR(xyz[1], num / den, 1e-14);

    // Independently: Simpson's rule on 0.05 nm steps of the interpolated tables; the 1 nm sum
    // is the midpoint rule for the box 499.5..600.5 nm (and 359.5..830.5 nm for the white).
    const auto simpson = [](double a, double b, int n) {
        const double h = (b - a) / n;
        double sum = 0.0;
        for (int i = 0; i <= n; ++i) {
            const double l = a + i * h;
            const double f = illuminant_d65(l) * cie_1931(l)[1];
            sum += f * (i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0);
        }
        return sum * h / 3.0;
    };
    const double y_numeric = simpson(499.5, 600.5, 2020) / simpson(359.5, 830.5, 9420);
    EXPECT_NEAR(xyz[1], y_numeric, 2e-4 * y_numeric);

    // colour-science 0.4.7, sd_to_XYZ of the same box: 0.44059672, 0.77522383, 0.04625849.
    EXPECT_NEAR(xyz[0], 0.44059672, 1e-6);
    EXPECT_NEAR(xyz[1], 0.77522383, 1e-6);
    EXPECT_NEAR(xyz[2], 0.04625849, 1e-6);
}

TEST(ColorXyz, CoarseAndFineListsAgreeForSmoothSpectra) {
    // Smooth, flat at 400 and 700 nm so that the constant extension of the coarse list fits.
    const auto f = [](double l) {
        const double x = std::clamp((l - 400.0) / 300.0, 0.0, 1.0);
        return 0.5 + 0.25 * std::cos(3.14159265358979323846 * x);
    };
    const auto coarse = grid(400.f, 700.f, 50.f);
    const auto fine = grid(360.f, 830.f, 1.f);
    std::vector<double> vc, vf;
    for (float l : coarse) vc.push_back(f(l));
    for (float l : fine) vf.push_back(f(l));
    const Xyz a = apply_weights(xyz_weights(coarse), vc);
    const Xyz b = apply_weights(xyz_weights(fine), vf);
    // The chords between 50 nm samples miss the curve by up to h^2 f'' / 8 ~ 0.009; weighted
    // by the observer that is about 1% in X and Z, 0.1% in Y (measured 0.0045 / 0.00035).
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], (c == 1 ? 0.002 : 0.015) * b[c]) << c;
    const Rgb ra = apply_weights(linear_srgb_weights(coarse), vc);
    const Rgb rb = apply_weights(linear_srgb_weights(fine), vf);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(ra[c], rb[c], 0.008) << c;  // measured 0.0051 in R
    // A 1 nm list holds the spectrum exactly: the same as integrating f itself.
    std::vector<double> wl(fine.begin(), fine.end());
    EXPECT_LT(max_abs_diff(b, spectrum_to_xyz(SampledSpectrum(wl, vf))), 1e-14);
}

TEST(ColorXyz, RejectsBadLists) {
    EXPECT_NE(error_of([] { xyz_weights({}); }).find("empty"), std::string::npos);
    EXPECT_NE(error_of([] { xyz_weights({500.f, 400.f}); }).find("ascending"), std::string::npos);
    EXPECT_NE(error_of([] { linear_srgb_weights({400.f, std::nanf("")}); }).find("non-finite"),
              std::string::npos);
    EXPECT_NE(error_of([] { luminance_weights({std::numeric_limits<float>::infinity()}); })
                  .find("non-finite"),
              std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// XYZ <-> linear sRGB, transfer functions

TEST(ColorRgb, MatricesAreTheSrgbOnes) {
    // IEC 61966-2-1 prints 4 digits: 0.4124 0.3576 0.1805 / 0.2126 0.7152 0.0722 / 0.0193 0.1192
    // 0.9505, and the inverse 3.2406 -1.5372 -0.4986 / -0.9689 1.8758 0.0415 / 0.0557 -0.2040
    // 1.0570 (the inverse of the rounded matrix, hence the looser tolerance).
    const double fwd[3][3] = {{0.4124, 0.3576, 0.1805}, {0.2126, 0.7152, 0.0722}, {0.0193, 0.1192, 0.9505}};
    const double inv[3][3] = {{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
    for (int c = 0; c < 3; ++c) {
        Rgb e{0.0, 0.0, 0.0};
        e[c] = 1.0;
        const Xyz col = linear_srgb_to_xyz(e);
        const Rgb icol = xyz_to_linear_srgb(e);
        for (int r = 0; r < 3; ++r) {
            EXPECT_NEAR(col[r], fwd[r][c], 6e-5) << r << c;
            EXPECT_NEAR(icol[r], inv[r][c], 6e-4) << r << c;
        }
    }
    // D65 white (x, y = 0.3127, 0.3290) and its 4-digit form.
    const Xyz white = linear_srgb_to_xyz({1.0, 1.0, 1.0});
    EXPECT_NEAR(white[0], 0.3127 / 0.3290, 1e-12);
    EXPECT_NEAR(white[1], 1.0, 1e-12);
    EXPECT_NEAR(white[2], (1.0 - 0.3127 - 0.3290) / 0.3290, 1e-12);
    EXPECT_LT(max_abs_diff(xyz_to_linear_srgb({0.9505, 1.0, 1.0888}), {1.0, 1.0, 1.0}), 1e-3);
}

TEST(ColorRgb, RoundTripsAndLuminance) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-0.5, 2.0);
    for (int i = 0; i < 100; ++i) {
        const Rgb rgb{u(rng), u(rng), u(rng)};
        EXPECT_LT(max_abs_diff(xyz_to_linear_srgb(linear_srgb_to_xyz(rgb)), rgb), 1e-13);
        const Xyz xyz{u(rng), u(rng), u(rng)};
        EXPECT_LT(max_abs_diff(linear_srgb_to_xyz(xyz_to_linear_srgb(xyz)), xyz), 1e-13);
        EXPECT_NEAR(linear_srgb_luminance(rgb), linear_srgb_to_xyz(rgb)[1], 1e-14);
    }
    EXPECT_NEAR(linear_srgb_luminance({1.0, 1.0, 1.0}), 1.0, 1e-14);
    EXPECT_NEAR(linear_srgb_luminance({1.0, 0.0, 0.0}), 0.2126, 5e-5);
    EXPECT_NEAR(linear_srgb_luminance({0.0, 1.0, 0.0}), 0.7152, 5e-5);
    EXPECT_NEAR(linear_srgb_luminance({0.0, 0.0, 1.0}), 0.0722, 5e-5);
}

TEST(ColorRgb, TransferFunctions) {
    EXPECT_EQ(srgb_to_linear(0.0), 0.0);
    EXPECT_NEAR(srgb_to_linear(1.0), 1.0, 1e-15);
    EXPECT_NEAR(srgb_to_linear(0.5), 0.214041140, 1e-9);
    EXPECT_NEAR(srgb_to_linear(0.04045), 0.04045 / 12.92, 1e-15);
    EXPECT_NEAR(linear_to_srgb(0.18), 0.461356129, 1e-9);
    EXPECT_NEAR(linear_to_srgb(1.0), 1.0, 1e-15);
    // The two pieces meet (to the standard's rounding of the break point).
    EXPECT_NEAR(linear_to_srgb(0.0031308), linear_to_srgb(std::nextafter(0.0031308, 1.0)), 1e-7);
    for (int i = -20; i <= 240; ++i) {
        const double e = i / 200.0;
        EXPECT_NEAR(linear_to_srgb(srgb_to_linear(e)), e, 1e-12) << e;
    }
}

// ---------------------------------------------------------------------------------------------
// Linear sRGB -> smooth reflectance spectrum

void expect_round_trip(const Rgb& rgb, double tol, double* worst = nullptr) {
    const SampledSpectrum s = linear_srgb_to_spectrum(rgb);
    const double err = max_abs_diff(xyz_to_linear_srgb(spectrum_to_xyz(s)), rgb);
    EXPECT_LT(err, tol) << rgb[0] << " " << rgb[1] << " " << rgb[2];
    if (worst) *worst = std::max(*worst, err);
}

bool within_unit_interval(const SampledSpectrum& s) {
    const auto [lo, hi] = std::minmax_element(s.values().begin(), s.values().end());
    return *lo >= 0.0 && *hi <= 1.0;
}

TEST(ColorUpsampling, GridIs360To830Every5nm) {
    const SampledSpectrum s = linear_srgb_to_spectrum({0.2, 0.4, 0.6});
    ASSERT_EQ(s.wavelengths().size(), 95u);
    EXPECT_EQ(s.wavelengths().front(), 360.0);
    EXPECT_EQ(s.wavelengths().back(), 830.0);
    EXPECT_EQ(s.wavelengths()[1] - s.wavelengths()[0], 5.0);
}

TEST(ColorUpsampling, RandomInGamutColoursRoundTripSmoothAndBounded) {
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double worst = 0.0, worst_d2 = 0.0;
    for (int i = 0; i < 200; ++i) {
        const Rgb rgb{u(rng), u(rng), u(rng)};
        const SampledSpectrum s = linear_srgb_to_spectrum(rgb);
        expect_round_trip(rgb, 1e-3, &worst);
        EXPECT_TRUE(within_unit_interval(s)) << rgb[0] << " " << rgb[1] << " " << rgb[2];
        worst_d2 = std::max(worst_d2, max_second_difference(s));
    }
    // Measured: round trip to ~1e-14; second differences below 0.02 per 5 nm step (a box-like
    // spectrum would have steps of order 1).
    EXPECT_LT(worst, 1e-9);
    EXPECT_LT(worst_d2, 0.04);
}

TEST(ColorUpsampling, PrimariesAndSecondaries) {
    const double k = 0.8;
    for (const Rgb& rgb : {Rgb{k, 0, 0}, Rgb{0, k, 0}, Rgb{0, 0, k}, Rgb{k, k, 0}, Rgb{0, k, k}, Rgb{k, 0, k}}) {
        const SampledSpectrum s = linear_srgb_to_spectrum(rgb);
        expect_round_trip(rgb, 1e-9);
        EXPECT_TRUE(within_unit_interval(s)) << rgb[0] << " " << rgb[1] << " " << rgb[2];
        EXPECT_LT(max_second_difference(s), 0.04);
    }
    // The spectra look like their colours: red reflects at 650 nm and not at 450 nm, etc.
    const SampledSpectrum red = linear_srgb_to_spectrum({k, 0, 0});
    EXPECT_GT(red(650.0), 0.5);
    EXPECT_LT(red(450.0), 0.05);
    const SampledSpectrum blue = linear_srgb_to_spectrum({0, 0, k});
    EXPECT_GT(blue(450.0), 0.5);
    EXPECT_LT(blue(620.0), 0.05);
}

TEST(ColorUpsampling, GreysAreNearlyFlat) {
    for (double g : {0.0, 0.18, 0.5, 0.9}) {
        const SampledSpectrum s = linear_srgb_to_spectrum({g, g, g});
        expect_round_trip({g, g, g}, 1e-9);
        for (double v : s.values()) EXPECT_NEAR(v, g, 1e-3) << g;
    }
    const SampledSpectrum black = linear_srgb_to_spectrum({0.0, 0.0, 0.0});
    for (double v : black.values()) EXPECT_EQ(v, 0.0);
}

TEST(ColorUpsampling, InfeasibleBoundsKeepTheColour) {
    // White: no spectrum within [0, 1] has exactly the matrix's white under the tabulated D65;
    // the result is nearly constant 1, a little above 1 in places, with the exact colour.
    const SampledSpectrum white = linear_srgb_to_spectrum({1.0, 1.0, 1.0});
    expect_round_trip({1.0, 1.0, 1.0}, 1e-9);
    for (double v : white.values()) EXPECT_NEAR(v, 1.0, 1e-3);
    // Brighter than a reflectance can be: non-negative, exact colour.
    for (const Rgb& rgb : {Rgb{2.0, 2.0, 2.0}, Rgb{1.5, 0.2, 0.2}, Rgb{0.3, 1.2, 0.9}}) {
        const SampledSpectrum s = linear_srgb_to_spectrum(rgb);
        expect_round_trip(rgb, 1e-9);
        EXPECT_GE(*std::min_element(s.values().begin(), s.values().end()), 0.0);
    }
    // Outside the spectral locus: values of both signs, still the exact colour.
    const Rgb impossible{-0.5, 1.0, -0.5};
    const SampledSpectrum s = linear_srgb_to_spectrum(impossible);
    expect_round_trip(impossible, 1e-9);
    EXPECT_LT(*std::min_element(s.values().begin(), s.values().end()), 0.0);
    EXPECT_NE(error_of([] { linear_srgb_to_spectrum({std::nan(""), 0.0, 0.0}); }).find("non-finite"),
              std::string::npos);
}

}  // namespace
