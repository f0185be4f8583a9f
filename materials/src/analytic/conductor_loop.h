// Exact unpolarised reflectance of air -> eta + i k (pbrt's FrConductor with eta_i = 1), at one
// angle for many wavelengths: out[j] for k[j].a = eta, k[j].b = k. Branch-free (selects; NaN takes
// the same side of each) so that the loop vectorises: fresnel.cpp includes it for any CPU and for
// single values, fresnel_avx2.cpp for AVX2 (chosen at run time by Fresnel::eval); without FMA both
// give the same bits. No interface (eta 1, k 0) reflects nothing (and would be 0/0 at c = 0); a
// non-finite result (degenerate limits) reflects everything. Include it inside the namespace that
// should own the copy, after <cmath>, <limits> and <npf/core/clamp.h>.

// c: |cos theta_d| clamped to [0, 1].
inline void conductor_reflectance_loop(double c, const npf::Fresnel::Coefficients* k, std::size_t n, double* out) {
    const double c2 = c * c, s2 = 1.0 - c2;
    for (std::size_t j = 0; j < n; ++j) {
        const double eta = k[j].a, kk = k[j].b;
        const double t0 = eta * eta - kk * kk - s2;
        const double a2b2 = std::sqrt(t0 * t0 + 4.0 * eta * eta * kk * kk);
        const double half = 0.5 * (a2b2 + t0);
        const double a = std::sqrt(clamp_low(half, 0.0));
        const double t1 = a2b2 + c2, t2 = 2.0 * c * a;
        const double rs = (t1 - t2) / (t1 + t2);
        const double t3 = c2 * a2b2 + s2 * s2, t4 = t2 * s2;
        const double rp = rs * (t3 - t4) / (t3 + t4);
        const double r = 0.5 * (rs + rp);
        const double finite = std::fabs(r) <= std::numeric_limits<double>::max() ? clamp_range(r, 0.0, 1.0) : 1.0;
        out[j] = eta == 1.0 && kk == 0.0 ? 0.0 : finite;
    }
}
