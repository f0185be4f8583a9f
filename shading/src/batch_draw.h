// The batched sample's draws as vector code (batch_draw_avx2.cpp): NpfClosure::draw_light's
// half-vector strategy four pairs at a time, with its arithmetic in its order (the alias table's
// steps in float, the cell's direction by HalfVectorSampler::direction_in_cell, the reflection in
// float), so that every lane gets the scalar draw's bits.
#pragma once

#include <npf/shading/half_vector_sampler.h>

#include <cstddef>
#include <cstdint>

namespace npf::batch_detail {

// Draws pairs [0, n - n % 4): light = reflect(view, h), or (0, 0, 0) where it falls at or below
// the horizon. Lanes that take the cosine strategy (u2 < diffuse_probability) or whose view is
// not above the horizon get redo[j] = 1 and nothing else: the caller draws them with the scalar
// code. Returns the number of pairs handled; 0 where this build has no AVX2.
std::size_t draw_lights_avx2(const HalfVectorSampler& sampler, double diffuse_probability, std::size_t n,
                             const float* const view[3], const float* u1, const float* u2, float* const light[3],
                             std::uint8_t* redo);

}  // namespace npf::batch_detail
