// npf::sin_cos (core/sin_cos.h) against the C library: within 2 ulp-sized steps (5e-16) of sin
// and cos over the sampler's range [0, 2 pi] and beyond (negative, a thousand turns), exact at 0,
// and at the quadrant boundaries where the reduction switches kernels.
#include <npf/core/sin_cos.h>
#include <npf/core/vec.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

void expect_close(double x) {
    double s = 0.0, c = 0.0;
    npf::sin_cos(x, s, c);
    ASSERT_NEAR(s, std::sin(x), 5e-16) << "sin " << x;
    ASSERT_NEAR(c, std::cos(x), 5e-16) << "cos " << x;
}

TEST(SinCos, MatchesTheLibraryOverTheSamplersRangeAndBeyond) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> turn(0.0, npf::kTwoPiD), wide(-6000.0, 6000.0);
    for (int i = 0; i < 200000; ++i) expect_close(turn(rng));
    for (int i = 0; i < 200000; ++i) expect_close(wide(rng));
    for (int k = -8; k <= 8; ++k) {
        const double edge = k * npf::kPiD / 4.0;  // where the nearest multiple of pi/2 changes
        for (double x : {std::nextafter(edge, -1e9), edge, std::nextafter(edge, 1e9)}) expect_close(x);
    }
    double s = 1.0, c = 0.0;
    npf::sin_cos(0.0, s, c);
    EXPECT_EQ(s, 0.0);
    EXPECT_EQ(c, 1.0);
}

}  // namespace
