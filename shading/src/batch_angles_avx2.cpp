// The angle kernels for AVX2: four pairs per step with table::generic's code on Double4
// (simd_double4.h), the rest of a block one pair at a time with the same code on double. This
// file alone is compiled with -mavx2 and without FMA (CMakeLists.txt), and called only where the
// CPU has AVX2 (npf_batch.cpp). Elsewhere (no GCC or Clang, not x86) it falls back to the
// portable kernels.
#include "batch_angles.h"

#if defined(__AVX2__)
#include "simd_double4.h"

#include <limits>

namespace npf::batch_detail {

namespace {

using simd::Double4;

template <bool DAzimuth, bool GAzimuth, bool Detail>
void angles(std::size_t n, const float* const view[3], const float* const light[3], BlockAngles& out) {
    constexpr AngleNeeds needs{DAzimuth, GAzimuth, Detail};
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        PairAnglesOf<Double4> a;
        pair_angles_of<Double4>(simd::load4(view[0] + i), simd::load4(view[1] + i), simd::load4(view[2] + i),
                                simd::load4(light[0] + i), simd::load4(light[1] + i), simd::load4(light[2] + i), needs, a);
        store_angles(out, i, a, [](double* p, Double4 v) { simd::store4(p, v); });
    }
    if (i < n) angles_portable(n - i, view, light, needs, out, i);
}

template <bool DAzimuth>
void half_vectors(std::size_t n, const float* const view[3], const float* const light[3], BlockHalfVectors& out) {
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        Double4 theta_h, u_h, phi_h, cos_d;
        half_vector_angles_of<Double4>(simd::load4(view[0] + i), simd::load4(view[1] + i), simd::load4(view[2] + i),
                                       simd::load4(light[0] + i), simd::load4(light[1] + i), simd::load4(light[2] + i),
                                       DAzimuth, theta_h, u_h, phi_h, cos_d);
        simd::store4(out.theta_h + i, theta_h);
        simd::store4(out.u_h + i, u_h);
        simd::store4(out.phi_h + i, phi_h);
        simd::store4(out.cos_d + i, cos_d);
    }
    if (i < n) half_vectors_portable(n - i, view, light, DAzimuth, out, i);
}

}  // namespace

void angles_avx2(std::size_t n, const float* const view[3], const float* const light[3], AngleNeeds needs, BlockAngles& out) {
    const int k = (needs.d_azimuth ? 4 : 0) + (needs.g_azimuth ? 2 : 0) + (needs.detail ? 1 : 0);
    switch (k) {
    case 0: return angles<false, false, false>(n, view, light, out);
    case 1: return angles<false, false, true>(n, view, light, out);
    case 2: return angles<false, true, false>(n, view, light, out);
    case 3: return angles<false, true, true>(n, view, light, out);
    case 4: return angles<true, false, false>(n, view, light, out);
    case 5: return angles<true, false, true>(n, view, light, out);
    case 6: return angles<true, true, false>(n, view, light, out);
    default: return angles<true, true, true>(n, view, light, out);
    }
}

void half_vectors_avx2(std::size_t n, const float* const view[3], const float* const light[3], bool d_azimuth,
                       BlockHalfVectors& out) {
    if (d_azimuth) return half_vectors<true>(n, view, light, out);
    return half_vectors<false>(n, view, light, out);
}

std::size_t domains_avx2(std::size_t n, const float* const view[3], const float* const light[3], std::uint8_t* valid) {
    // Both z above 0 and every component finite (|x| <= the largest float: false for NaN).
    const __m256 largest = _mm256_set1_ps(std::numeric_limits<float>::max()), zero = _mm256_setzero_ps();
    const __m256 sign = _mm256_set1_ps(-0.f);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        __m256 ok = _mm256_and_ps(_mm256_cmp_ps(_mm256_loadu_ps(view[2] + i), zero, _CMP_GT_OQ),
                                  _mm256_cmp_ps(_mm256_loadu_ps(light[2] + i), zero, _CMP_GT_OQ));
        for (const float* const* d : {view, light}) {
            for (int c = 0; c < 3; ++c)
                ok = _mm256_and_ps(ok, _mm256_cmp_ps(_mm256_andnot_ps(sign, _mm256_loadu_ps(d[c] + i)), largest, _CMP_LE_OQ));
        }
        // The lanes (all ones or 0) as eight bytes of 1 or 0: packed to 16, then 8 bits per
        // 128-bit half, whose first four bytes each are the half's lanes.
        const __m256i one = _mm256_and_si256(_mm256_castps_si256(ok), _mm256_set1_epi32(1));
        const __m256i bytes = _mm256_packs_epi16(_mm256_packs_epi32(one, one), _mm256_setzero_si256());
        _mm_storel_epi64(reinterpret_cast<__m128i*>(valid + i),
                         _mm_unpacklo_epi32(_mm256_castsi256_si128(bytes), _mm256_extracti128_si256(bytes, 1)));
    }
    return i;
}

}  // namespace npf::batch_detail

#else

namespace npf::batch_detail {

void angles_avx2(std::size_t n, const float* const view[3], const float* const light[3], AngleNeeds needs, BlockAngles& out) {
    angles_portable(n, view, light, needs, out);
}

void half_vectors_avx2(std::size_t n, const float* const view[3], const float* const light[3], bool d_azimuth,
                       BlockHalfVectors& out) {
    half_vectors_portable(n, view, light, d_azimuth, out);
}

std::size_t domains_avx2(std::size_t, const float* const[3], const float* const[3], std::uint8_t*) { return 0; }

}  // namespace npf::batch_detail

#endif
