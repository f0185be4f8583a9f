// Eight floats in an AVX2 register: simd_double4.h's operations for the batched closure's float
// lanes (BatchPrecision::Float, npf_batch.h), so that the same generic code (table::generic, the
// angle and axis rules) runs on them. Not bit-equal to the double path: within the float budget
// of docs/shading.md. Included only by the files compiled for AVX2.
#pragma once

#include <immintrin.h>

#include <cstdint>
#include <limits>

namespace npf::simd {

struct Mask8 {
    __m256 m;
};

struct Float8 {
    __m256 v;
    Float8() = default;
    Float8(double x) : v(_mm256_set1_ps(float(x))) {}  // NOLINT: the generic code's constants are doubles
    explicit Float8(__m256 x) : v(x) {}
};

inline Float8 operator+(Float8 a, Float8 b) { return Float8(_mm256_add_ps(a.v, b.v)); }
inline Float8 operator-(Float8 a, Float8 b) { return Float8(_mm256_sub_ps(a.v, b.v)); }
inline Float8 operator*(Float8 a, Float8 b) { return Float8(_mm256_mul_ps(a.v, b.v)); }
inline Float8 operator/(Float8 a, Float8 b) { return Float8(_mm256_div_ps(a.v, b.v)); }
inline Float8 operator-(Float8 a) { return Float8(_mm256_xor_ps(a.v, _mm256_set1_ps(-0.f))); }

inline Mask8 operator>(Float8 a, Float8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)}; }
inline Mask8 operator<(Float8 a, Float8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)}; }
inline Mask8 operator==(Float8 a, Float8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)}; }
inline Mask8 operator||(Mask8 a, Mask8 b) { return {_mm256_or_ps(a.m, b.m)}; }
inline bool any(Mask8 a) { return _mm256_movemask_ps(a.m) != 0; }
inline Mask8 operator!(Mask8 a) { return {_mm256_xor_ps(a.m, _mm256_castsi256_ps(_mm256_set1_epi32(-1)))}; }

inline Float8 select(Mask8 c, Float8 a, Float8 b) { return Float8(_mm256_blendv_ps(b.v, a.v, c.m)); }
inline Float8 abs(Float8 a) { return Float8(_mm256_andnot_ps(_mm256_set1_ps(-0.f), a.v)); }
inline Float8 sqrt(Float8 a) { return Float8(_mm256_sqrt_ps(a.v)); }
inline Float8 trunc(Float8 a) { return Float8(_mm256_round_ps(a.v, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC)); }
inline Float8 floor(Float8 a) { return Float8(_mm256_round_ps(a.v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)); }

// Whole numbers below 2^24 (cell indices; every table is smaller) as eight int32, exactly.
inline __m256i to_int32(Float8 a) { return _mm256_cvtps_epi32(a.v); }
// table[index[k]] for each lane: eight scalar loads (see simd_double4.h's gather on vgatherdps).
inline Float8 gather(const float* table, __m256i index) {
    alignas(32) int i[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(i), index);
    return Float8(_mm256_setr_ps(table[i[0]], table[i[1]], table[i[2]], table[i[3]], table[i[4]], table[i[5]], table[i[6]],
                                 table[i[7]]));
}

// finite_float (finite_float.h) on eight lanes: infinities to float's largest, NaN to 0.
inline Float8 finite_float_of(Float8 v) {
    constexpr float kMax = std::numeric_limits<float>::max();
    const Float8 clamped = select(v < Float8(-kMax), Float8(-kMax), select(Float8(kMax) < v, Float8(kMax), v));
    return select(v == v, clamped, Float8(0.0));
}

// table::generic::atan_reduced for the float lanes (found by argument-dependent lookup):
// q + q^3 P(q^2) with P of degree 3 instead of 6, a least-squares fit on Chebyshev nodes over
// |q| <= tan(pi/8); error 5e-9 rad, below float's rounding of the angle.
inline Float8 atan_reduced(Float8 q) {
    const Float8 s = q * q, s2 = s * s;
    const Float8 p = (Float8(-0.3333272681618652) + Float8(0.1997103619422266) * s) +
                     s2 * (Float8(-0.1381710885730751) + Float8(0.0788242842006463) * s);
    return q + q * s * p;
}

// Lanes whose byte (a block's valid[], 1 or 0) is not 0: the eight bytes widened, then != 0.
inline Mask8 nonzero_bytes8(const std::uint8_t* b) {
    const __m256i lanes = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(b)));
    return {_mm256_castsi256_ps(_mm256_xor_si256(_mm256_cmpeq_epi32(lanes, _mm256_setzero_si256()), _mm256_set1_epi32(-1)))};
}

inline Float8 load8(const float* p) { return Float8(_mm256_loadu_ps(p)); }
inline void store8(float* p, Float8 a) { _mm256_storeu_ps(p, a.v); }

}  // namespace npf::simd
