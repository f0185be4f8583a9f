// Random numbers for the renderer: counter-based, so that every number is a pure function of
// (seed, pixel, sample, dimension) and the image does not depend on threads or scheduling.
//
// There is no generator state to carry from one sample to the next. A pixel's samples come from
// a `PixelSampler`, which hands out 2D points for (sample index, dimension pair):
//  - the N points of one dimension pair form a rank-1 lattice {(i / N, i g / N) mod 1} with
//    g coprime to N (g near N / phi^2, a Fibonacci-like generator), so that each of the two 1D
//    projections puts exactly one point in each of N equal strata;
//  - the lattice is shifted by a random offset (Cranley-Patterson rotation) drawn from
//    (seed, pixel, dimension pair), which makes every single point uniform on [0, 1)^2 and the
//    average over the N points an unbiased estimate;
//  - the sample index is permuted per (seed, pixel, dimension pair) by a bijection of [0, N),
//    so that the pairs of one sample (pixel position, light sample, BSDF sample) are not
//    correlated with each other.
// Because the numbers depend on nothing else, two renders that differ only in the material use
// the same pixel positions, the same light-sample points and the same BSDF-sample points
// ("shared random numbers"; docs/render.md).
#pragma once

#include <npf/core/vec.h>

#include <cstdint>

namespace npf::render {

// SplitMix64's output function (Steele, Lea & Flood 2014): a bijective 64-bit mixer.
inline std::uint64_t mix64(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

// A hash of several words: each is mixed into the running value in order.
inline std::uint64_t hash_words(std::uint64_t a, std::uint64_t b) {
    return mix64(a ^ mix64(b + 0x9e3779b97f4a7c15ULL));
}
inline std::uint64_t hash_words(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
    return hash_words(hash_words(a, b), c);
}
inline std::uint64_t hash_words(std::uint64_t a, std::uint64_t b, std::uint64_t c, std::uint64_t d) {
    return hash_words(hash_words(a, b, c), d);
}

// A bijection of [0, n) chosen by `key` (n >= 1): a keyed invertible mixer on the smallest
// power-of-two range that holds n, iterated until the value falls below n (cycle walking).
std::uint32_t permute_index(std::uint32_t index, std::uint32_t n, std::uint64_t key);

// The lattice generator used for n points: the integer nearest n (3 - sqrt 5) / 2 that is
// coprime to n (1 for n <= 2).
std::uint32_t lattice_generator(std::uint32_t n);

// The sample points of one pixel.
class PixelSampler {
public:
    // `samples` >= 1 is the pixel's sample count N.
    PixelSampler(std::uint64_t seed, std::uint64_t pixel, std::uint32_t samples);

    // The point of sample `sample` (< N) in dimension pair `dimension`, in [0, 1)^2.
    Vec2 get_2d(std::uint32_t sample, std::uint32_t dimension) const;

    std::uint32_t samples() const { return m_samples; }

private:
    std::uint64_t m_key;  // hash of (seed, pixel)
    std::uint32_t m_samples;
    std::uint32_t m_generator;
};

}  // namespace npf::render
