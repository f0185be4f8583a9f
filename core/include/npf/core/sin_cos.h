// sin and cos of one angle together, inline and branch-free: the half-vector sampler turns every
// drawn azimuth into a direction, and the C library's sincos (a call, with a slow path for huge
// arguments) was a third of a sample's time. Accurate to about 1 ulp of double for |x| up to
// about 1e6 rad (the sampler's angles are in [0, 2 pi]); the callers round the result to float.
// Range reduction to [-pi/4, pi/4] by the nearest multiple of pi/2 in two parts (Cody and
// Waite), then the minimax kernels of fdlibm (k_sin.c, k_cos.c).
#pragma once

#include <cmath>

namespace npf {

inline void sin_cos(double x, double& s, double& c) {
    constexpr double kTwoOverPi = 6.36619772367581382433e-01;
    constexpr double kPiOver2Hi = 1.57079632673412561417e+00;  // 33 bits: k * hi is exact
    constexpr double kPiOver2Lo = 6.07710050650619224932e-11;
    const double k = std::floor(x * kTwoOverPi + 0.5);
    const double r = (x - k * kPiOver2Hi) - k * kPiOver2Lo;
    const double z = r * r;
    const double sin_r = r + r * z * (-1.66666666666666324348e-01 +
                                      z * (8.33333333332248946124e-03 +
                                           z * (-1.98412698298579493134e-04 +
                                                z * (2.75573137070700676789e-06 +
                                                     z * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10)))));
    const double tail = z * z * (4.16666666666666019037e-02 +
                                 z * (-1.38888888888741095749e-03 +
                                      z * (2.48015872894767294178e-05 +
                                           z * (-2.75573143513906633035e-07 +
                                                z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11)))));
    const double half_z = 0.5 * z, w = 1.0 - half_z;
    const double cos_r = w + (((1.0 - w) - half_z) + tail);
    // The quadrant: k mod 4.
    const int q = int(k - 4.0 * std::floor(k * 0.25));
    const double sq[4] = {sin_r, cos_r, -sin_r, -cos_r};
    s = sq[q];
    c = sq[(q + 1) & 3];
}

}  // namespace npf
