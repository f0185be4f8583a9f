// The CIE observer and D65, spectrum -> XYZ (and the per-wavelength weights for it), XYZ <->
// linear sRGB, and the sRGB transfer functions.
#include "cie_tables.h"

#include <npf/color/spectrum.h>
#include <npf/core/error.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace npf::color {

namespace {

using namespace detail;

// Linear interpolation in a table of `count` values `step_nm` apart from `first_nm`; zero
// outside the table (and for NaN).
double table_lookup(const double* table, int count, int first_nm, int step_nm, double lambda_nm) {
    const double x = (lambda_nm - first_nm) / step_nm;
    if (!(x >= 0.0) || x > count - 1) return 0.0;
    const int i = std::min(static_cast<int>(x), count - 2);
    const double t = x - i;
    return (1.0 - t) * table[i] + t * table[i + 1];
}

// The integration rule of the colour convention: a sum over the whole nanometres 360..830 of
// S(l) E_D65(l) cmf(l), divided by the same sum for E_D65 ybar. weight[c][i] is the factor of
// S(360 + i) in channel c.
struct Integration {
    double weight[3][kCmfCount];
};

const Integration& integration() {
    static const Integration table = [] {
        Integration t{};
        double norm = 0.0;
        for (int i = 0; i < kCmfCount; ++i) norm += illuminant_d65(kCmfFirstNm + i) * kCie1931Y[i];
        for (int i = 0; i < kCmfCount; ++i) {
            const double e = illuminant_d65(kCmfFirstNm + i) / norm;
            t.weight[0][i] = e * kCie1931X[i];
            t.weight[1][i] = e * kCie1931Y[i];
            t.weight[2][i] = e * kCie1931Z[i];
        }
        return t;
    }();
    return table;
}

using Mat3 = std::array<std::array<double, 3>, 3>;

Mat3 inverse(const Mat3& m) {
    Mat3 r{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            // Cofactor of m[j][i] (adjugate = transposed cofactors), cyclic indices.
            const int j1 = (j + 1) % 3, j2 = (j + 2) % 3, i1 = (i + 1) % 3, i2 = (i + 2) % 3;
            r[i][j] = m[j1][i1] * m[j2][i2] - m[j1][i2] * m[j2][i1];
        }
    const double det = m[0][0] * r[0][0] + m[0][1] * r[1][0] + m[0][2] * r[2][0];
    for (auto& row : r)
        for (double& v : row) v /= det;
    return r;
}

// IEC 61966-2-1 (sRGB): Rec. 709 primaries and the D65 white x = 0.3127, y = 0.3290, Y = 1.
// Derived at full precision rather than the standard's 4-digit print, so that the two
// matrices are exact inverses (0.4123908 0.3575843 0.1804808 / 0.2126390 0.7151687 0.0721923 /
// 0.0193308 0.1191948 0.9505322).
struct Matrices {
    Mat3 rgb_to_xyz, xyz_to_rgb;
};

const Matrices& matrices() {
    static const Matrices m = [] {
        const double primaries[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
        const double wx = 0.3127, wy = 0.3290;
        Mat3 p{};  // columns: XYZ of each primary with Y = 1
        for (int c = 0; c < 3; ++c) {
            const double x = primaries[c][0], y = primaries[c][1];
            p[0][c] = x / y;
            p[1][c] = 1.0;
            p[2][c] = (1.0 - x - y) / y;
        }
        const Mat3 p_inv = inverse(p);
        const double white[3] = {wx / wy, 1.0, (1.0 - wx - wy) / wy};
        Matrices out{};
        for (int c = 0; c < 3; ++c) {
            // Scale each primary so that RGB (1, 1, 1) is the white.
            const double scale = p_inv[c][0] * white[0] + p_inv[c][1] * white[1] + p_inv[c][2] * white[2];
            for (int r = 0; r < 3; ++r) out.rgb_to_xyz[r][c] = p[r][c] * scale;
        }
        out.xyz_to_rgb = inverse(out.rgb_to_xyz);
        return out;
    }();
    return m;
}

std::array<double, 3> apply(const Mat3& m, const std::array<double, 3>& v) {
    return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
            m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

}  // namespace

Xyz cie_1931(double lambda_nm) {
    return {table_lookup(kCie1931X, kCmfCount, kCmfFirstNm, 1, lambda_nm),
            table_lookup(kCie1931Y, kCmfCount, kCmfFirstNm, 1, lambda_nm),
            table_lookup(kCie1931Z, kCmfCount, kCmfFirstNm, 1, lambda_nm)};
}

double illuminant_d65(double lambda_nm) {
    return table_lookup(kD65, kD65Count, kD65FirstNm, kD65StepNm, lambda_nm);
}

Xyz spectrum_to_xyz(const SampledSpectrum& s) {
    const Integration& in = integration();
    Xyz xyz{0.0, 0.0, 0.0};
    if (s.empty()) return xyz;
    for (int i = 0; i < kCmfCount; ++i) {
        const double v = s(kCmfFirstNm + i);
        for (int c = 0; c < 3; ++c) xyz[c] += in.weight[c][i] * v;
    }
    return xyz;
}

std::array<std::vector<double>, 3> xyz_weights(const std::vector<float>& wavelengths_nm) {
    const std::size_t n = wavelengths_nm.size();
    if (n == 0) throw Error("wavelength list", "empty: no samples to weigh");
    for (std::size_t k = 0; k < n; ++k) {
        if (!std::isfinite(wavelengths_nm[k])) throw Error("wavelength list", "non-finite wavelength");
        if (k > 0 && wavelengths_nm[k] < wavelengths_nm[k - 1]) {
            std::ostringstream msg;
            msg << "wavelengths must be in ascending order (" << wavelengths_nm[k] << " nm after "
                << wavelengths_nm[k - 1] << " nm)";
            throw Error("wavelength list", msg.str());
        }
    }
    // S(l) = sum_k v_k hat_k(l) exactly (piecewise linear, constant beyond the ends), so the
    // weight of sample k is the 1 nm sum of hat_k times the integration weights. The hats sum
    // to 1 everywhere, hence a constant spectrum gets the white's XYZ (Y = 1) for any list.
    // Repeated wavelengths are a jump: the first takes the interval on its left, the last the
    // interval on its right.
    const Integration& in = integration();
    std::array<std::vector<double>, 3> w;
    for (auto& channel : w) channel.assign(n, 0.0);
    for (int i = 0; i < kCmfCount; ++i) {
        const double l = kCmfFirstNm + i;
        // Last sample at or below l.
        const auto it = std::upper_bound(wavelengths_nm.begin(), wavelengths_nm.end(), l,
                                         [](double a, float b) { return a < static_cast<double>(b); });
        std::size_t k0 = 0, k1 = 0;
        double t = 0.0;
        if (it == wavelengths_nm.begin()) {
            k0 = k1 = 0;
        } else if (it == wavelengths_nm.end()) {
            k0 = k1 = n - 1;
        } else {
            k1 = static_cast<std::size_t>(it - wavelengths_nm.begin());
            k0 = k1 - 1;
            const double a = wavelengths_nm[k0], b = wavelengths_nm[k1];  // a <= l < b
            t = (l - a) / (b - a);
        }
        for (int c = 0; c < 3; ++c) {
            w[c][k0] += (1.0 - t) * in.weight[c][i];
            w[c][k1] += t * in.weight[c][i];
        }
    }
    return w;
}

std::array<std::vector<double>, 3> linear_srgb_weights(const std::vector<float>& wavelengths_nm) {
    const auto xyz = xyz_weights(wavelengths_nm);
    const Mat3& m = matrices().xyz_to_rgb;
    std::array<std::vector<double>, 3> rgb;
    for (int r = 0; r < 3; ++r) {
        rgb[r].resize(wavelengths_nm.size());
        for (std::size_t k = 0; k < wavelengths_nm.size(); ++k)
            rgb[r][k] = m[r][0] * xyz[0][k] + m[r][1] * xyz[1][k] + m[r][2] * xyz[2][k];
    }
    return rgb;
}

std::vector<double> luminance_weights(const std::vector<float>& wavelengths_nm) {
    return std::move(xyz_weights(wavelengths_nm)[1]);
}

Rgb xyz_to_linear_srgb(const Xyz& xyz) { return apply(matrices().xyz_to_rgb, xyz); }

Xyz linear_srgb_to_xyz(const Rgb& rgb) { return apply(matrices().rgb_to_xyz, rgb); }

double linear_srgb_luminance(const Rgb& rgb) {
    // The Y row of the matrix: 0.2126390, 0.7151687, 0.0721923, the Rec. 709 weights at full
    // precision, so that this equals linear_srgb_to_xyz(rgb)[1].
    const Mat3& m = matrices().rgb_to_xyz;
    return m[1][0] * rgb[0] + m[1][1] * rgb[1] + m[1][2] * rgb[2];
}

// IEC 61966-2-1. Below the linear-segment threshold the straight line continues to negative
// values; above 1 the power law continues, so out-of-range values survive a round trip.
double srgb_to_linear(double encoded) {
    if (encoded <= 0.04045) return encoded / 12.92;
    return std::pow((encoded + 0.055) / 1.055, 2.4);
}

double linear_to_srgb(double linear) {
    if (linear <= 0.0031308) return 12.92 * linear;
    return 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

}  // namespace npf::color
