// The float lanes' angle kernel (BatchPrecision::Float): eight pairs per step with table::generic's
// code on Float8 (simd_float8.h). Apart from batch_angles_avx2.cpp because this file is compiled
// with FMA and contracted multiply-adds (CMakeLists.txt): the float lanes are held to the float
// budget of docs/shading.md, not to the bit, and the double path must keep its bits. Called only
// where the CPU has AVX2 and FMA (npf_batch.cpp).
#include "batch_angles.h"

#if defined(__AVX2__)
#include "simd_float8.h"

namespace npf::batch_detail {

namespace {

using simd::Float8;

template <bool DAzimuth, bool GAzimuth, bool Detail>
std::size_t angles_float(std::size_t n, const float* const view[3], const float* const light[3], BlockAnglesOf<float>& out) {
    constexpr AngleNeeds needs{DAzimuth, GAzimuth, Detail};
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        PairAnglesOf<Float8> a;
        pair_angles_of<Float8>(simd::load8(view[0] + i), simd::load8(view[1] + i), simd::load8(view[2] + i),
                               simd::load8(light[0] + i), simd::load8(light[1] + i), simd::load8(light[2] + i), needs, a);
        store_angles(out, i, a, [](float* p, Float8 v) { simd::store8(p, v); });
    }
    return i;
}

}  // namespace

std::size_t angles_float_avx2(std::size_t n, const float* const view[3], const float* const light[3], AngleNeeds needs,
                              BlockAnglesOf<float>& out) {
    const int k = (needs.d_azimuth ? 4 : 0) + (needs.g_azimuth ? 2 : 0) + (needs.detail ? 1 : 0);
    switch (k) {
    case 0: return angles_float<false, false, false>(n, view, light, out);
    case 1: return angles_float<false, false, true>(n, view, light, out);
    case 2: return angles_float<false, true, false>(n, view, light, out);
    case 3: return angles_float<false, true, true>(n, view, light, out);
    case 4: return angles_float<true, false, false>(n, view, light, out);
    case 5: return angles_float<true, false, true>(n, view, light, out);
    case 6: return angles_float<true, true, false>(n, view, light, out);
    default: return angles_float<true, true, true>(n, view, light, out);
    }
}

}  // namespace npf::batch_detail

#else

namespace npf::batch_detail {

std::size_t angles_float_avx2(std::size_t, const float* const[3], const float* const[3], AngleNeeds, BlockAnglesOf<float>&) {
    return 0;  // no float lanes in this build: the caller takes the double path
}

}  // namespace npf::batch_detail

#endif
