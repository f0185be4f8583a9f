// Batched shading: eval and pdf of an NpfClosure over many direction pairs at once, as wavefront
// and SIMD renderers and numpy callers hand them over. Directions come as structure-of-arrays;
// the angle work of a block of pairs and, on the memory path, its table lookups and values run as
// vector code four pairs at a time (AVX2 where the CPU has it; else the scalar code pair by pair).
// With BatchPrecision::Double, results equal the scalar closure's to the bit on either instruction
// set (the same arithmetic, no fused multiply-add; the choice is npf/core/simd_isa.h's), which
// shading/tests/test_batch_closure.cpp checks. BatchPrecision::Float evaluates eight pairs at a time in
// float lanes within a stated error budget (docs/shading.md; shading/tests/test_batch_float.cpp).
#pragma once

#include <cstddef>

namespace npf {

// n directions: x[i], y[i], z[i] (the closure's local frame, unit vectors).
struct DirectionArrays {
    const float* x = nullptr;
    const float* y = nullptr;
    const float* z = nullptr;
};

// The wavelengths a batched eval answers: none (null nm: every stored channel, RGB always),
// `count` shared by every pair (nm[k]), or `count` per pair (nm[i * count + k], hero
// wavelengths).
struct BatchWavelengths {
    const float* nm = nullptr;
    int count = 0;
    bool per_pair = false;

    static BatchWavelengths stored() { return {}; }
    static BatchWavelengths shared(const float* nm, int count) { return {nm, count, false}; }
    static BatchWavelengths each_pair(const float* nm, int count) { return {nm, count, true}; }
};

// The arithmetic of the batched eval's values (and of sample_batch's weights): double lanes, the
// scalar closure's bits; or float lanes, where the renders agree with the double path at 80 dB
// or more and the BRDF-space relative RMS of the difference is at most 1e-4 (the float budget,
// docs/shading.md). Float needs AVX2; elsewhere it is the double path. pdf_batch and the draws
// are double either way; eval_batch's pdf (so sample_batch's pdf where it asks for weights) is
// computed in the float lanes too.
enum class BatchPrecision { Double, Float };

}  // namespace npf
