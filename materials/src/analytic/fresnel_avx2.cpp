// The conductor loop (conductor_loop.h) for AVX2: this file alone is compiled with -mavx2 and
// without FMA (converter/CMakeLists.txt), and runs only where the CPU has AVX2 (Fresnel::eval).
#include "fresnel_avx2.h"

#if defined(__AVX2__)
#include <npf/core/clamp.h>

#include <cmath>
#include <limits>

namespace npf::fresnel_detail::avx2 {
namespace {
#include "conductor_loop.h"
}  // namespace

bool conductor_reflectances(double c, const Fresnel::Coefficients* k, std::size_t n, double* out) {
    conductor_reflectance_loop(c, k, n, out);
    return true;
}

}  // namespace npf::fresnel_detail::avx2
#else
namespace npf::fresnel_detail::avx2 {
bool conductor_reflectances(double, const Fresnel::Coefficients*, std::size_t, double*) { return false; }
}  // namespace npf::fresnel_detail::avx2
#endif
