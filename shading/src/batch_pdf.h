// The batched closure's pdf as vector code (batch_pdf_avx2.cpp): NpfClosure::pdf_at four pairs at
// a time from a block's half-vector angles, with its arithmetic in its order (the sampler's cell,
// its pmf over its solid angle, the mixture with the cosine strategy, finite_float), so that every
// lane gets the scalar pdf's bits.
#pragma once

#include <npf/shading/half_vector_sampler.h>

#include <cstddef>
#include <cstdint>

namespace npf::batch_detail {

// pdf[j] = pdf_at(theta_h[j], u_h[j], phi_h[j], cos_d[j], cos_light[j]) for j in [0, n - n % 4),
// and 0 where valid (if not null) has valid[j] == 0, a pair outside the domain; without `valid`
// whatever the pair's domain (the caller zeroes pairs outside it). Returns the number of pairs
// written: 0 where this build has no AVX2, the sampler is empty or the cosine strategy is the
// only one (the caller's scalar code covers those).
std::size_t pdfs_avx2(const HalfVectorSampler& sampler, double diffuse_probability, std::size_t n, const double* theta_h,
                      const double* u_h, const double* phi_h, const double* cos_d, const double* cos_light,
                      const std::uint8_t* valid, float* pdf);
// The same in float lanes, eight pairs at a time, from float angles (BatchPrecision::Float): the
// same steps, within float's rounding of the double pdf ([0, n - n % 8)).
std::size_t pdfs_float_avx2(const HalfVectorSampler& sampler, double diffuse_probability, std::size_t n, const float* theta_h,
                            const float* u_h, const float* phi_h, const float* cos_d, const float* cos_light,
                            const std::uint8_t* valid, float* pdf);

}  // namespace npf::batch_detail
