// Where a value falls on a factor table whose samples sit at cell centres (centre of cell k at
// k + 1/2, in cell units): the two cells to blend and the weight of the second. One definition
// for the fitter's tables (NpfFactors) and the stored model (NpfModel), so that a file
// evaluates exactly as the fit that wrote it (docs/format.md).
#pragma once

#include <npf/core/vec.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace npf::table {

struct Lerp {
    int i0 = 0, i1 = 0;
    double t = 0.0;  // weight of i1
};

// The three axis rules below are written once, generic over the number type (as the angle
// functions further down): `double` for the scalar lookups and the fitter, a vector of doubles for
// the batched closure (npf_batch.h), so that both find the same cells and weights to the bit. The
// generic forms keep the cell indices as whole numbers of the same type; the scalar forms return
// them as int. Inputs are finite (a caller with NaN gets meaningless cells, as before).
template <class T>
struct LerpOf {
    T i0, i1, t;
};

namespace generic {

// Inlined always: the batched closure calls these on vectors, and a call per function (with
// the vector arguments passed through memory) cost a third of its angle work.
#if defined(__GNUC__) || defined(__clang__)
#define NPF_GENERIC_INLINE [[gnu::always_inline]] inline
#else
#define NPF_GENERIC_INLINE inline
#endif

inline double select(bool c, double a, double b) { return c ? a : b; }
inline bool any(bool c) { return c; }
inline double abs(double x) { return std::fabs(x); }
inline double sqrt(double x) { return std::sqrt(x); }
// Whole cells: the axis rules truncate values in [0, 2^31) only (finite inputs), where the
// conversion through an integer is std::trunc; it is a single instruction on any x86-64, where
// std::trunc without SSE4.1 is a sequence that slowed the scalar evaluation by a sixth.
inline double trunc(double x) { return double(static_cast<long long>(x)); }
inline double floor(double x) { return std::floor(x); }

// Clamped at the outer centres (theta axes of D and F): std::clamp and std::min, written as
// selects.
template <class T>
inline LerpOf<T> clamped(T x, int n) {
    const T last = T(double(n - 1)), v = x - T(0.5);
    const T c = select(v < T(0.0), T(0.0), select(last < v, last, v));
    LerpOf<T> l;
    l.i0 = trunc(c);  // c <= last: no min needed
    l.i1 = select(last < l.i0 + T(1.0), last, l.i0 + T(1.0));
    l.t = c - l.i0;
    return l;
}

// Periodic (phi axes). Azimuths arrive in [0, 2 pi), so one wrap of the lower half cell covers
// them; anything else takes the general (floor) form. Rounding can put the wrapped value at n
// itself: cell n - 1 at t = 1 then.
template <class T>
inline LerpOf<T> periodic(T x, int n) {
    const T count = T(double(n)), last = T(double(n - 1));
    T c = x - T(0.5);
    c = select(c < T(0.0), c + count, c);
    const auto outside = c < T(0.0) || !(c < count);
    if (any(outside)) c = select(outside, c - floor(c / count) * count, c);  // rare: one branch
    LerpOf<T> l;
    const T whole = trunc(c);
    l.i0 = select(last < whole, last, whole);
    l.i1 = select(l.i0 + T(1.0) == count, T(0.0), l.i0 + T(1.0));
    l.t = c - l.i0;
    return l;
}

// G's theta axis: flat below the first centre, and beyond the last one continued along the
// line through the last two rows (t > 1), so that G can fall to 0 at grazing angles, as the
// fitter's interpolation does (fit/sample_set.h). Callers clamp the result at 0.
template <class T>
inline LerpOf<T> extrapolated(T x, int n) {
    if (n == 1) return {T(0.0), T(0.0), T(0.0)};
    const T before_last = T(double(n - 2)), v = x - T(0.5);
    const T c = select(T(0.0) < v, v, T(0.0));
    LerpOf<T> l;
    const T whole = trunc(c);
    l.i0 = select(before_last < whole, before_last, whole);
    l.i1 = l.i0 + T(1.0);
    l.t = c - l.i0;
    return l;
}

// The weights of bilinear()'s four corners.
template <class T>
inline void bilinear_weights(T row_t, T col_t, T w[4]) {
    w[0] = (T(1.0) - row_t) * (T(1.0) - col_t);
    w[1] = (T(1.0) - row_t) * col_t;
    w[2] = row_t * (T(1.0) - col_t);
    w[3] = row_t * col_t;
}

}  // namespace generic

inline Lerp to_lerp(const LerpOf<double>& l) { return {int(l.i0), int(l.i1), l.t}; }
inline Lerp clamped(double x, int n) { return to_lerp(generic::clamped<double>(x, n)); }
inline Lerp periodic(double x, int n) { return to_lerp(generic::periodic<double>(x, n)); }
inline Lerp extrapolated(double x, int n) { return to_lerp(generic::extrapolated<double>(x, n)); }

// The four corners of a 2D table (row-major, `cols` per row) around a position and their
// weights, from a Lerp along each axis.
struct Bilinear {
    std::size_t index[4];
    double weight[4];
};

inline Bilinear bilinear(const Lerp& row, const Lerp& col, int cols) {
    Bilinear b;
    const std::size_t r0 = std::size_t(row.i0) * std::size_t(cols), r1 = std::size_t(row.i1) * std::size_t(cols);
    b.index[0] = r0 + std::size_t(col.i0);
    b.index[1] = r0 + std::size_t(col.i1);
    b.index[2] = r1 + std::size_t(col.i0);
    b.index[3] = r1 + std::size_t(col.i1);
    generic::bilinear_weights<double>(row.t, col.t, b.weight);
    return b;
}

// The angle functions of the shading hot path. Each evaluation computes four polar angles and,
// for anisotropic tables, three azimuths; with std::atan2 and branchy range reduction they cost
// more than every table lookup together (random directions defeat the branch predictor). So:
// range reduction by selects (short, mostly compiled to conditional moves), one division, and a
// polynomial evaluated in Estrin's scheme for a short dependency chain. Measured on random
// directions: polar 6 ns and azimuth 5 ns, against 20 ns for atan2(sqrt(x^2 + y^2), z) with
// std::atan2 (2.6 GHz EPYC; writing the selects as arithmetic on 0/1 made them slower).

// Written once, generic over the number type: `double` for the scalar closure, a vector of
// doubles for the batched one (npf_batch.h), with the same operations in the same order, so both
// give the same bits. Selects stand for branches (select(c, a, b) = c ? a : b, both computed).
namespace generic {

// atan(q) for |q| <= tan(pi/8): q + q^3 P(q^2), P a degree-6 least-squares fit on Chebyshev
// nodes; error below 2e-13 rad, far below any table's cell (the finest is ~0.25 degree).
template <class T>
NPF_GENERIC_INLINE T atan_reduced(T q) {
    const T s = q * q, s2 = s * s, s4 = s2 * s2;
    const T p01 = T(-0.3333333325178168) + T(0.19999990368499) * s;
    const T p23 = T(-0.14285295313834662) + T(0.11102007775528105) * s;
    const T p45 = T(-0.08980719194750149) + T(0.06926031589253447) * s;
    const T p = (p01 + s2 * p23) + s4 * (p45 + s2 * T(-0.03688082797610674));
    return q + q * s * p;
}

// atan(small / big) in [0, pi/4] for 0 <= small <= big: past tan(pi/8) the identity
// atan(r) = pi/4 + atan((r - 1) / (r + 1)) keeps the polynomial's argument small. (0, 0) gives 0.
template <class T>
NPF_GENERIC_INLINE T atan_ratio(T small, T big) {
    constexpr double kTanPiOver8 = 0.41421356237309503, kQuarterPi = 0.25 * kPiD;
    const auto shift = small > T(kTanPiOver8) * big;
    const T num = select(shift, small - big, small);
    const T den = select(shift, small + big, select(big == T(0.0), T(1.0), big));
    return select(shift, T(kQuarterPi), T(0.0)) + atan_reduced(num / den);
}

template <class T>
NPF_GENERIC_INLINE T atan2(T y, T x) {
    const T ax = abs(x), ay = abs(y);
    const auto swap = ay > ax;
    T r = atan_ratio(select(swap, ax, ay), select(swap, ay, ax));
    r = select(swap, T(kHalfPiD) - r, r);
    r = select(x < T(0.0), T(kPiD) - r, r);
    return select(y < T(0.0), -r, r);
}

template <class T>
NPF_GENERIC_INLINE T polar_of(T r, T z) {
    const T az = abs(z);
    const auto swap = r > az;
    T a = atan_ratio(select(swap, az, r), select(swap, r, az));
    a = select(swap, T(kHalfPiD) - a, a);
    return select(z < T(0.0), T(kPiD) - a, a);
}

template <class T>
NPF_GENERIC_INLINE T polar(T x, T y, T z) {
    return polar_of(sqrt(x * x + y * y), z);
}

template <class T>
NPF_GENERIC_INLINE T azimuth(T x, T y) {
    const T phi = generic::atan2(y, x);
    return select(phi < T(0.0), phi + T(kTwoPiD), phi);
}

}  // namespace generic

// atan2(y, x) in (-pi, pi], accurate to 3e-13 rad. atan2(0, 0) is 0; NaN in, NaN out.
inline double atan2(double y, double x) { return generic::atan2<double>(y, x); }

// Angle from +z, in [0, pi], of a vector whose distance from the z axis is r >= 0: atan2(r, z),
// which keeps the angle accurate near the pole, where acos loses half the digits.
inline double polar_of(double r, double z) { return generic::polar_of<double>(r, z); }

// Angle from +z and azimuth in [0, 2 pi) of a direction.
inline double polar(double x, double y, double z) { return generic::polar<double>(x, y, z); }
inline double azimuth(double x, double y) { return generic::azimuth<double>(x, y); }

}  // namespace npf::table
