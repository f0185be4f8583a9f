// The AVX2 build of the conductor loop (fresnel_avx2.cpp).
#pragma once

#include <npf/materials/analytic/fresnel.h>

#include <cstddef>

namespace npf::fresnel_detail::avx2 {

// conductor_loop.h's loop; false (nothing written) where this build has no AVX2.
bool conductor_reflectances(double c, const Fresnel::Coefficients* k, std::size_t n, double* out);

}  // namespace npf::fresnel_detail::avx2
