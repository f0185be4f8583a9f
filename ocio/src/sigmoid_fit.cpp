// Fitting a sigmoid-polynomial spectrum to a linear sRGB colour (Jakob & Hanika 2019).
#include "sigmoid_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace npf::color::detail {

namespace {

constexpr int kFineCount = 471;    // 360..830 nm every 1 nm
constexpr int kCoarseCount = 95;   // every 5 nm
constexpr double kMaxCoefficient = 200.0;

// Where the spectrum is evaluated (normalised wavelengths) and what each value weighs in X, Y, Z.
struct Rule {
    std::vector<double> x;
    std::array<std::vector<double>, 3> w;
};

std::vector<float> whole_nanometres() {
    std::vector<float> g(kFineCount);
    for (int i = 0; i < kFineCount; ++i) g[i] = static_cast<float>(kSigmoidFirstNm + i);
    return g;
}

Rule exact_rule() {
    Rule r;
    r.w = xyz_weights(whole_nanometres());  // exactly spectrum_to_xyz's weights
    r.x.resize(kFineCount);
    for (int i = 0; i < kFineCount; ++i) r.x[i] = i / kSigmoidSpanNm;
    return r;
}

// Each 1 nm value is the cubic through the four nearest 5 nm values (Lagrange form), so its
// weight is spread over those four nodes.
Rule coarse_rule() {
    const auto fine = xyz_weights(whole_nanometres());
    Rule r;
    r.x.resize(kCoarseCount);
    for (int k = 0; k < kCoarseCount; ++k) r.x[k] = 5.0 * k / kSigmoidSpanNm;
    for (auto& w : r.w) w.assign(kCoarseCount, 0.0);
    for (int i = 0; i < kFineCount; ++i) {
        const int first = std::clamp(i / 5 - 1, 0, kCoarseCount - 4);
        const double t = i / 5.0 - first;  // position in node steps from `first`
        for (int a = 0; a < 4; ++a) {
            double basis = 1.0;
            for (int b = 0; b < 4; ++b)
                if (b != a) basis *= (t - b) / (a - b);
            for (int c = 0; c < 3; ++c) r.w[c][first + a] += basis * fine[c][i];
        }
    }
    return r;
}

const Rule& rule(Quadrature q) {
    static const Rule exact = exact_rule();
    static const Rule coarse = coarse_rule();
    return q == Quadrature::Exact ? exact : coarse;
}

using Mat3 = std::array<std::array<double, 3>, 3>;

// The spectrum's XYZ and its derivatives with respect to the three coefficients.
void colour_and_jacobian(const Rule& r, const SigmoidCoefficients& c, std::array<double, 3>& xyz, Mat3& d_xyz) {
    const std::size_t n = r.x.size();
    // Values and slopes first (independent per point, so the square roots pipeline), then
    // the sums with two accumulators each for the same reason.
    double s[kFineCount], g[kFineCount];
    for (std::size_t i = 0; i < n; ++i) {
        const double x = r.x[i];
        const double p = (c[0] * x + c[1]) * x + c[2];
        const double q2 = 1.0 / (1.0 + p * p);
        const double q = std::sqrt(q2);
        s[i] = 0.5 + 0.5 * p * q;  // S(p)
        g[i] = 0.5 * q * q2;       // S'(p) = 1 / (2 (1 + p^2)^(3/2))
    }
    for (int k = 0; k < 3; ++k) {
        const double* w = r.w[k].data();
        double v[2] = {0, 0}, d2[2] = {0, 0}, d1[2] = {0, 0}, d0[2] = {0, 0};
        for (std::size_t i = 0; i < n; ++i) {
            const int lane = static_cast<int>(i & 1);
            const double x = r.x[i], wg = w[i] * g[i];
            v[lane] += w[i] * s[i];
            d0[lane] += wg;
            d1[lane] += wg * x;
            d2[lane] += wg * x * x;
        }
        xyz[k] = v[0] + v[1];
        d_xyz[k] = {d2[0] + d2[1], d1[0] + d1[1], d0[0] + d0[1]};
    }
}

// CIELAB of `xyz` relative to the sRGB white, and its derivatives with respect to XYZ.
struct LabWhite {
    std::array<double, 3> white;
    LabWhite() {
        const Xyz w = linear_srgb_to_xyz({1.0, 1.0, 1.0});
        white = {w[0], w[1], w[2]};
    }
};

void lab(const std::array<double, 3>& xyz, std::array<double, 3>& out, Mat3* d_lab) {
    static const LabWhite lw;
    constexpr double delta = 6.0 / 29.0;
    double f[3], df[3];
    for (int c = 0; c < 3; ++c) {
        const double t = xyz[c] / lw.white[c];
        if (t > delta * delta * delta) {
            f[c] = std::cbrt(t);
            df[c] = 1.0 / (3.0 * f[c] * f[c] * lw.white[c]);
        } else {
            f[c] = t / (3.0 * delta * delta) + 4.0 / 29.0;
            df[c] = 1.0 / (3.0 * delta * delta * lw.white[c]);
        }
    }
    out = {116.0 * f[1] - 16.0, 500.0 * (f[0] - f[1]), 200.0 * (f[1] - f[2])};
    if (d_lab) {
        *d_lab = Mat3{};
        (*d_lab)[0][1] = 116.0 * df[1];
        (*d_lab)[1][0] = 500.0 * df[0];
        (*d_lab)[1][1] = -500.0 * df[1];
        (*d_lab)[2][1] = 200.0 * df[1];
        (*d_lab)[2][2] = -200.0 * df[2];
    }
}

double det3(const Mat3& m) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

// Cramer's rule; false for a singular or non-finite system.
bool solve3(const Mat3& a, const std::array<double, 3>& b, std::array<double, 3>& x) {
    const double det = det3(a);
    if (!std::isfinite(det) || std::abs(det) < 1e-300) return false;
    for (int k = 0; k < 3; ++k) {
        Mat3 m = a;
        for (int r = 0; r < 3; ++r) m[r][k] = b[r];
        x[k] = det3(m) / det;
    }
    return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

}  // namespace

double fit_sigmoid(const Rgb& rgb, SigmoidCoefficients& c, Quadrature quadrature, double tolerance_squared,
                   int max_iterations) {
    const Rule& r = rule(quadrature);
    const Xyz t = linear_srgb_to_xyz(rgb);
    std::array<double, 3> target{};
    lab({t[0], t[1], t[2]}, target, nullptr);

    SigmoidCoefficients best = c;
    double best_residual = std::numeric_limits<double>::infinity();
    for (int it = 0; it < max_iterations; ++it) {
        std::array<double, 3> xyz{}, current{}, residual{}, step{};
        Mat3 d_xyz{}, d_lab{}, jacobian{};
        colour_and_jacobian(r, c, xyz, d_xyz);
        lab(xyz, current, &d_lab);
        double r2 = 0.0;
        for (int k = 0; k < 3; ++k) {
            residual[k] = target[k] - current[k];
            r2 += residual[k] * residual[k];
        }
        if (!std::isfinite(r2)) break;
        if (r2 < best_residual) best = c, best_residual = r2;
        if (r2 < tolerance_squared) break;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                jacobian[i][j] = d_lab[i][0] * d_xyz[0][j] + d_lab[i][1] * d_xyz[1][j] + d_lab[i][2] * d_xyz[2][j];
        if (!solve3(jacobian, residual, step)) break;
        for (int k = 0; k < 3; ++k) c[k] += step[k];
        const double largest = std::max({std::abs(c[0]), std::abs(c[1]), std::abs(c[2])});
        if (largest > kMaxCoefficient)
            for (double& v : c) v *= kMaxCoefficient / largest;
    }
    c = best;
    return best_residual;
}

}  // namespace npf::color::detail
