// Four doubles in an AVX2 register, with the operations table::generic's code uses
// (table_interpolation.h): + - * / sqrt abs, trunc floor, comparisons to masks, select, gathers
// from float tables. Each is the IEEE operation per lane, as the scalar code's, so results agree
// to the bit. Included only by the files compiled for AVX2 (batch_angles_avx2.cpp,
// batch_values_avx2.cpp).
#pragma once

#include <immintrin.h>

#include <cstdint>
#include <limits>

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
inline Mask4 operator||(Mask4 a, Mask4 b) { return {_mm256_or_pd(a.m, b.m)}; }
inline bool any(Mask4 a) { return _mm256_movemask_pd(a.m) != 0; }
inline Mask4 operator!(Mask4 a) { return {_mm256_xor_pd(a.m, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)))}; }

inline Double4 select(Mask4 c, Double4 a, Double4 b) { return Double4(_mm256_blendv_pd(b.v, a.v, c.m)); }
inline Double4 abs(Double4 a) { return Double4(_mm256_andnot_pd(_mm256_set1_pd(-0.0), a.v)); }
inline Double4 sqrt(Double4 a) { return Double4(_mm256_sqrt_pd(a.v)); }

// Rounding to whole numbers (table_interpolation.h's cells), exact as std::trunc and std::floor.
inline Double4 trunc(Double4 a) { return Double4(_mm256_round_pd(a.v, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC)); }
inline Double4 floor(Double4 a) { return Double4(_mm256_round_pd(a.v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)); }

// Whole numbers in int32 range (cell indices) as four int32, exactly.
inline __m128i to_int32(Double4 a) { return _mm256_cvtpd_epi32(a.v); }
// table[index[k]] for each lane, as doubles. Four scalar loads: on this project's AMD Zen 3 machine
// they beat vgatherdps (microcoded there) by 9-11 % of the whole batched eval (docs/shading.md).
inline Double4 gather(const float* table, __m128i index) {
    const __m128 v = _mm_setr_ps(table[_mm_cvtsi128_si32(index)], table[_mm_extract_epi32(index, 1)],
                                 table[_mm_extract_epi32(index, 2)], table[_mm_extract_epi32(index, 3)]);
    return Double4(_mm256_cvtps_pd(v));
}

// sin_cos_of's two steps (npf/core/sin_cos.h) on four lanes: floor, and entry q of four values
// chosen by masks.
inline Double4 floor_of(Double4 a) { return floor(a); }
inline Double4 quadrant_pick(Double4 q, Double4 a0, Double4 a1, Double4 a2, Double4 a3) {
    return select(q == Double4(0.0), a0, select(q == Double4(1.0), a1, select(q == Double4(2.0), a2, a3)));
}

// finite_float's steps (finite_float.h) on four lanes, before the conversion to float: clamped to
// float's range, NaN to 0.
inline Double4 finite_float_of(Double4 v) {
    constexpr double kMax = std::numeric_limits<float>::max();
    const Double4 clamped = select(v < Double4(-kMax), Double4(-kMax), select(Double4(kMax) < v, Double4(kMax), v));
    return select(v == v, clamped, Double4(0.0));
}

// Lanes whose byte (a block's valid[], 1 or 0) is not 0: all ones there, zeros elsewhere.
inline Mask4 nonzero_bytes4(const std::uint8_t* b) {
    return {_mm256_castsi256_pd(_mm256_set_epi64x(-std::int64_t(b[3] != 0), -std::int64_t(b[2] != 0), -std::int64_t(b[1] != 0),
                                                  -std::int64_t(b[0] != 0)))};
}

inline Double4 load4(const double* p) { return Double4(_mm256_loadu_pd(p)); }
inline Double4 load4(const float* p) { return Double4(_mm256_cvtps_pd(_mm_loadu_ps(p))); }
inline void store4(double* p, Double4 a) { _mm256_storeu_pd(p, a.v); }

}  // namespace npf::simd
