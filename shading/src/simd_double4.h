// Four doubles in an AVX2 register, with the operations table::generic's angle code uses
// (table_interpolation.h): + - * / sqrt abs, comparisons to masks, select. Each is the IEEE
// operation per lane, as the scalar code's, so results agree to the bit. Included only by the
// file compiled for AVX2 (batch_angles_avx2.cpp).
#pragma once

#include <immintrin.h>

namespace npf::simd {

struct Mask4 {
    __m256d m;
};

struct Double4 {
    __m256d v;
    Double4() = default;
    Double4(double x) : v(_mm256_set1_pd(x)) {}  // NOLINT: constants mix with vectors freely
    explicit Double4(__m256d x) : v(x) {}
};

inline Double4 operator+(Double4 a, Double4 b) { return Double4(_mm256_add_pd(a.v, b.v)); }
inline Double4 operator-(Double4 a, Double4 b) { return Double4(_mm256_sub_pd(a.v, b.v)); }
inline Double4 operator*(Double4 a, Double4 b) { return Double4(_mm256_mul_pd(a.v, b.v)); }
inline Double4 operator/(Double4 a, Double4 b) { return Double4(_mm256_div_pd(a.v, b.v)); }
inline Double4 operator-(Double4 a) { return Double4(_mm256_xor_pd(a.v, _mm256_set1_pd(-0.0))); }

// Ordered, quiet comparisons: false where either is NaN, as in C++.
inline Mask4 operator>(Double4 a, Double4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_GT_OQ)}; }
inline Mask4 operator<(Double4 a, Double4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LT_OQ)}; }
inline Mask4 operator==(Double4 a, Double4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_EQ_OQ)}; }
inline Mask4 operator!(Mask4 a) { return {_mm256_xor_pd(a.m, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)))}; }

inline Double4 select(Mask4 c, Double4 a, Double4 b) { return Double4(_mm256_blendv_pd(b.v, a.v, c.m)); }
inline Double4 abs(Double4 a) { return Double4(_mm256_andnot_pd(_mm256_set1_pd(-0.0), a.v)); }
inline Double4 sqrt(Double4 a) { return Double4(_mm256_sqrt_pd(a.v)); }

inline Double4 load4(const float* p) { return Double4(_mm256_cvtps_pd(_mm_loadu_ps(p))); }
inline void store4(double* p, Double4 a) { _mm256_storeu_pd(p, a.v); }

}  // namespace npf::simd
