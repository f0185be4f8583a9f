// Where a value falls on a factor table whose samples sit at cell centres (centre of cell k at
// k + 1/2, in cell units): the two cells to blend and the weight of the second. One definition
// for the fitter's tables (NpfFactors) and the stored model (NpfModel), so that a file
// evaluates exactly as the fit that wrote it (docs/format.md).
#pragma once

#include <npf/core/vec.h>

#include <algorithm>
#include <cmath>

namespace npf::table {

struct Lerp {
    int i0 = 0, i1 = 0;
    double t = 0.0;  // weight of i1
};

// Clamped at the outer centres (theta axes of D and F).
inline Lerp clamped(double x, int n) {
    Lerp l;
    const double c = std::clamp(x - 0.5, 0.0, double(n - 1));
    l.i0 = std::min(int(c), n - 1);
    l.i1 = std::min(l.i0 + 1, n - 1);
    l.t = c - l.i0;
    return l;
}

// Periodic (phi axes).
inline Lerp periodic(double x, int n) {
    Lerp l;
    double c = x - 0.5;
    c -= std::floor(c / n) * n;
    l.i0 = std::min(int(c), n - 1);
    l.i1 = (l.i0 + 1) % n;
    l.t = c - l.i0;
    return l;
}

// G's theta axis: flat below the first centre, and beyond the last one continued along the
// line through the last two rows (t > 1), so that G can fall to 0 at grazing angles, as the
// fitter's interpolation does (fit/sample_set.h). Callers clamp the result at 0.
inline Lerp extrapolated(double x, int n) {
    Lerp l;
    if (n == 1) return l;
    const double c = std::max(0.0, x - 0.5);
    l.i0 = std::min(int(c), n - 2);
    l.i1 = l.i0 + 1;
    l.t = c - l.i0;
    return l;
}

// atan2(y, x) in (-pi, pi], accurate to 2e-15 rad, several times faster than std::atan2: the
// shading hot path computes up to seven angles per evaluation. Range reduction to
// |t| <= tan(pi/8), then t + t^3 P(t^2) with P a degree-8 fit (Chebyshev nodes) of
// (atan t - t) / t^3. Signed zeros and infinities are not special-cased beyond what the
// arithmetic gives; NaN in, NaN out.
inline double atan2(double y, double x) {
    constexpr double kTanPiOver8 = 0.41421356237309503, kQuarterPi = 0.78539816339744831;
    const double ax = std::fabs(x), ay = std::fabs(y);
    const bool swap = ay > ax;
    const double big = swap ? ay : ax, small = swap ? ax : ay;
    if (big == 0.0) return 0.0;
    // One division either way: atan(small / big), or pi/4 + atan((small - big) / (small + big))
    // once the ratio passes tan(pi/8).
    const bool shift = small > kTanPiOver8 * big;
    const double t = shift ? (small - big) / (small + big) : small / big;
    const double s = t * t;
    double p = -0.027265716714484144;
    p = p * s + 0.05171104301492307;
    p = p * s - 0.06551544747143043;
    p = p * s + 0.07681138474580866;
    p = p * s - 0.09090263517299882;
    p = p * s + 0.11111089982599119;
    p = p * s - 0.14285713937600766;
    p = p * s + 0.19999999997784587;
    p = p * s - 0.3333333333333103;
    double r = (shift ? kQuarterPi : 0.0) + (t + t * s * p);  // atan(small / big), in [0, pi/4]
    if (swap) r = 2.0 * kQuarterPi - r;
    if (x < 0.0) r = 4.0 * kQuarterPi - r;
    return y < 0.0 ? -r : r;
}

// Angle from +z and azimuth in [0, 2 pi) of a direction; atan2 keeps the polar angle accurate
// near the pole, where acos loses half the digits.
inline double polar(double x, double y, double z) { return table::atan2(std::sqrt(x * x + y * y), z); }
inline double azimuth(double x, double y) {
    const double phi = table::atan2(y, x);
    return phi < 0.0 ? phi + 2.0 * kPiD : phi;
}

}  // namespace npf::table
