#include <npf/render/rng.h>

#include <cmath>
#include <numeric>

namespace npf::render {

namespace {

// Largest float below 1.
constexpr float kOneMinusUlp = 0.99999994f;

float wrap_unit(double x) {
    x -= std::floor(x);
    const float f = float(x);
    return f < 1.f ? f : kOneMinusUlp;
}

}  // namespace

std::uint32_t permute_index(std::uint32_t index, std::uint32_t n, std::uint64_t key) {
    if (n <= 1) return 0;
    // Smallest mask 2^k - 1 >= n - 1.
    std::uint32_t mask = n - 1;
    mask |= mask >> 1, mask |= mask >> 2, mask |= mask >> 4, mask |= mask >> 8, mask |= mask >> 16;
    int bits = 0;
    while (bits < 32 && (mask >> bits)) ++bits;
    const std::uint32_t shift = std::uint32_t(bits + 1) / 2;  // >= 1: xorshift by it is invertible on k bits
    const std::uint32_t k0 = std::uint32_t(key), k1 = std::uint32_t(key >> 32);
    std::uint32_t x = index;
    do {
        // Every step is a bijection of [0, 2^k): xor with a constant, multiplication by an odd
        // number modulo 2^k, addition modulo 2^k, xorshift right.
        x ^= k0 & mask;
        x = (x * (k1 | 1u)) & mask;
        x ^= x >> shift;
        x = (x + (k1 >> 7)) & mask;
        x = (x * 0x2c1b3c6du) & mask;  // odd
        x ^= x >> shift;
        x ^= (k0 >> 11) & mask;
        x = (x * ((k0 >> 3) | 1u)) & mask;
        x ^= x >> shift;
    } while (x >= n);
    return x;
}

std::uint32_t lattice_generator(std::uint32_t n) {
    if (n <= 2) return 1;
    const double c = (3.0 - std::sqrt(5.0)) / 2.0;  // 1 / phi^2
    std::uint32_t g = std::uint32_t(std::lround(double(n) * c));
    if (g < 1) g = 1;
    while (std::gcd(g, n) != 1) ++g;
    return g;
}

PixelSampler::PixelSampler(std::uint64_t seed, std::uint64_t pixel, std::uint32_t samples)
    : m_key(hash_words(seed, pixel)), m_samples(samples < 1 ? 1 : samples), m_generator(lattice_generator(m_samples)) {}

Vec2 PixelSampler::get_2d(std::uint32_t sample, std::uint32_t dimension) const {
    const std::uint64_t h = hash_words(m_key, dimension);
    const std::uint32_t i = permute_index(sample % m_samples, m_samples, mix64(h ^ 0x5bd1e995ULL));
    const std::uint64_t s = mix64(h + 0x632be59bd9b4e019ULL);
    const double sx = double(std::uint32_t(s)) * (1.0 / 4294967296.0);
    const double sy = double(std::uint32_t(s >> 32)) * (1.0 / 4294967296.0);
    const double n = double(m_samples);
    const std::uint64_t j = (std::uint64_t(i) * m_generator) % m_samples;
    return {wrap_unit(double(i) / n + sx), wrap_unit(double(j) / n + sy)};
}

}  // namespace npf::render
