// Batched shading: eval and pdf of an NpfClosure over many direction pairs at once, as wavefront
// and SIMD renderers and numpy callers hand them over. Directions come as structure-of-arrays;
// the angle work of a block of pairs and, on the memory path, its table lookups and values run as
// vector code four pairs at a time (AVX2 where the CPU has it; else the scalar code pair by pair).
// Results equal the scalar closure's to the bit on either instruction set (the same arithmetic,
// no fused multiply-add; the choice is npf/core/simd_isa.h's), which tests/test_batch_closure.cpp
// checks.
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

}  // namespace npf
