// The renderer's counter-based random numbers (npf/render/rng.h): index permutations are
// bijections, a pixel's N points are stratified in each coordinate, everything is a pure
// function of (seed, pixel, sample, dimension).
#include <npf/render/rng.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numeric>
#include <set>
#include <vector>

namespace {

using npf::render::PixelSampler;

TEST(RenderRng, PermutationIsABijection) {
    for (std::uint32_t n : {1u, 2u, 3u, 5u, 7u, 16u, 63u, 64u, 65u, 100u, 1000u, 4097u}) {
        for (std::uint64_t key : {0ull, 1ull, 0x123456789abcdefull, ~0ull}) {
            std::vector<bool> seen(n, false);
            for (std::uint32_t i = 0; i < n; ++i) {
                const std::uint32_t p = npf::render::permute_index(i, n, key);
                ASSERT_LT(p, n) << "n " << n;
                EXPECT_FALSE(seen[p]) << "n " << n << " key " << key << " index " << i;
                seen[p] = true;
            }
        }
    }
    // Different keys give different orders (for n large enough to tell).
    int same = 0;
    for (std::uint32_t i = 0; i < 64; ++i) same += npf::render::permute_index(i, 64, 1) == npf::render::permute_index(i, 64, 2);
    EXPECT_LT(same, 16);
}

TEST(RenderRng, LatticeGeneratorIsCoprime) {
    for (std::uint32_t n = 1; n < 2000; ++n) {
        const std::uint32_t g = npf::render::lattice_generator(n);
        EXPECT_EQ(std::gcd(g, n), 1u) << n;
        EXPECT_GE(g, 1u);
    }
    EXPECT_EQ(npf::render::lattice_generator(64), 25u);  // 64 (3 - sqrt 5) / 2 = 24.4 -> 24, not coprime -> 25
}

TEST(RenderRng, PixelPointsAreStratifiedInEachCoordinate) {
    for (std::uint32_t n : {1u, 2u, 16u, 37u, 64u, 256u}) {
        const PixelSampler sampler(7, 12345, n);
        for (std::uint32_t dim = 0; dim < 3; ++dim) {
            std::vector<int> xs(n, 0), ys(n, 0);
            for (std::uint32_t s = 0; s < n; ++s) {
                const npf::Vec2 p = sampler.get_2d(s, dim);
                ASSERT_GE(p.x, 0.f);
                ASSERT_LT(p.x, 1.f);
                ASSERT_GE(p.y, 0.f);
                ASSERT_LT(p.y, 1.f);
                ++xs[std::min<std::size_t>(n - 1, std::size_t(p.x * float(n)))];
                ++ys[std::min<std::size_t>(n - 1, std::size_t(p.y * float(n)))];
            }
            // A random shift moves every point by the same amount, so each stratum of width 1/N
            // (shifted) holds exactly one: counted on the fixed grid, no cell holds more than 2.
            for (std::uint32_t k = 0; k < n; ++k) {
                EXPECT_LE(xs[k], 2) << "n " << n << " dim " << dim;
                EXPECT_LE(ys[k], 2) << "n " << n << " dim " << dim;
            }
        }
    }
}

TEST(RenderRng, PurelyAFunctionOfItsInputs) {
    const PixelSampler a(1, 99, 64), b(1, 99, 64), other_seed(2, 99, 64), other_pixel(1, 100, 64);
    int differ_seed = 0, differ_pixel = 0, differ_dim = 0;
    for (std::uint32_t s = 0; s < 64; ++s) {
        for (std::uint32_t d = 0; d < 3; ++d) {
            const npf::Vec2 p = a.get_2d(s, d), q = b.get_2d(s, d);
            EXPECT_EQ(p.x, q.x);
            EXPECT_EQ(p.y, q.y);
            differ_seed += other_seed.get_2d(s, d).x != p.x;
            differ_pixel += other_pixel.get_2d(s, d).x != p.x;
        }
        differ_dim += a.get_2d(s, 0).x != a.get_2d(s, 1).x;
    }
    EXPECT_GT(differ_seed, 180);
    EXPECT_GT(differ_pixel, 180);
    EXPECT_GT(differ_dim, 60);
}

TEST(RenderRng, DimensionPairsAreNotCorrelated) {
    // Over many pixels, the sample's first coordinate in pair 0 and pair 1 must look independent:
    // a sample correlation near 0 (the permutation decorrelates the pairs of one sample).
    const std::uint32_t n = 16;
    double sxy = 0, sx = 0, sy = 0, sxx = 0, syy = 0;
    int count = 0;
    for (std::uint64_t pixel = 0; pixel < 2000; ++pixel) {
        const PixelSampler s(3, pixel, n);
        for (std::uint32_t i = 0; i < n; ++i) {
            const double x = s.get_2d(i, 0).x, y = s.get_2d(i, 1).x;
            sxy += x * y, sx += x, sy += y, sxx += x * x, syy += y * y;
            ++count;
        }
    }
    const double c = count;
    const double corr = (sxy / c - sx / c * sy / c) / std::sqrt((sxx / c - sx * sx / c / c) * (syy / c - sy * sy / c / c));
    EXPECT_LT(std::fabs(corr), 0.02) << corr;
    // And the mean of a coordinate is 1/2.
    EXPECT_NEAR(sx / c, 0.5, 0.005);
}

}  // namespace
