// sin and cos of one angle together, inline and branch-free: the half-vector sampler turns every
// drawn azimuth into a direction, and the C library's sincos (a call, with a slow path for huge
// arguments) was a third of a sample's time. Accurate to about 1 ulp of double for |x| up to
// about 1e6 rad (the sampler's angles are in [0, 2 pi]); the callers round the result to float.
// Range reduction to [-pi/4, pi/4] by the nearest multiple of pi/2 in two parts (Cody and
// Waite), then the minimax kernels of fdlibm (k_sin.c, k_cos.c).
#pragma once

#include <cmath>

namespace npf {

namespace sin_cos_detail {
inline double floor_of(double x) { return std::floor(x); }
// Entry q (0..3) of {a0, a1, a2, a3}: an indexed load, no branch (a vector type overloads it with
// selects).
inline double quadrant_pick(double q, double a0, double a1, double a2, double a3) {
    const double v[4] = {a0, a1, a2, a3};
    return v[int(q)];
}
}  // namespace sin_cos_detail

// Generic over the number type: double here, four doubles in the batched sampler (whose type
// provides floor_of and quadrant_pick beside it), with the same operations in the same order.
// Always inlined: a vector instantiation must not leave a weak symbol that a build for another
// instruction set could share (tests/check_isa_objects.cmake).
template <class T>
#if defined(__GNUC__) || defined(__clang__)
[[gnu::always_inline]]
#endif
inline void sin_cos_of(T x, T& s, T& c) {
    using sin_cos_detail::floor_of;
    using sin_cos_detail::quadrant_pick;
    constexpr double kTwoOverPi = 6.36619772367581382433e-01;
    constexpr double kPiOver2Hi = 1.57079632673412561417e+00;  // 33 bits: k * hi is exact
    constexpr double kPiOver2Lo = 6.07710050650619224932e-11;
    const T k = floor_of(x * T(kTwoOverPi) + T(0.5));
    const T r = (x - k * T(kPiOver2Hi)) - k * T(kPiOver2Lo);
    const T z = r * r;
    const T sin_r = r + r * z * (T(-1.66666666666666324348e-01) +
                                 z * (T(8.33333333332248946124e-03) +
                                      z * (T(-1.98412698298579493134e-04) +
                                           z * (T(2.75573137070700676789e-06) +
                                                z * (T(-2.50507602534068634195e-08) + z * T(1.58969099521155010221e-10))))));
    const T tail = z * z * (T(4.16666666666666019037e-02) +
                            z * (T(-1.38888888888741095749e-03) +
                                 z * (T(2.48015872894767294178e-05) +
                                      z * (T(-2.75573143513906633035e-07) +
                                           z * (T(2.08757232129817482790e-09) + z * T(-1.13596475577881948265e-11))))));
    const T half_z = T(0.5) * z, w = T(1.0) - half_z;
    const T cos_r = w + (((T(1.0) - w) - half_z) + tail);
    // The quadrant: k mod 4.
    const T q = k - T(4.0) * floor_of(k * T(0.25));
    s = quadrant_pick(q, sin_r, cos_r, -sin_r, -cos_r);
    c = quadrant_pick(q, cos_r, -sin_r, -cos_r, sin_r);
}

inline void sin_cos(double x, double& s, double& c) { sin_cos_of(x, s, c); }

}  // namespace npf
