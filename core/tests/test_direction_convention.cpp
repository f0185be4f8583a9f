// The direction convention (docs/conventions.md), tested where a flip would hide: npf::Brdf and
// NpfModel take the conditioned, camera-side direction first (wi) and weight by the other's
// cosine (wo); NpfClosure names the two by role (view, light). The NPF model is reciprocal, so a
// flipped pair changes only the cosine factor and the density the sampler integrates to one over:
// both are checked with the two directions at very different heights, on a mostly diffuse
// material, where the cosines and the sampling densities of the two orders differ by a factor
// of three or more.
#include "npf_test_factors.h"

#include <npf/fit/npf_factors.h>
#include <npf/fit/spectral_compression.h>
#include <npf/core/brdf.h>
#include <npf/core/vec.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_closure.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace {

using npf::ClosureSample, npf::NpfBrdf, npf::NpfClosure, npf::NpfModel, npf::Vec3, npf::WavelengthRequest;

NpfModel mostly_diffuse() {
    npf::testing::MicrofacetSpec spec;
    spec.alpha_x = spec.alpha_y = 0.35;
    spec.rho_d = 0.5;
    spec.rho_s = 0.15;
    return npf::compress_factors(npf::testing::make_microfacet_factors(spec), npf::CompressionOptions());
}

Vec3 at(double theta_deg, double phi_deg) {
    const double t = theta_deg * npf::kPiD / 180.0, p = phi_deg * npf::kPiD / 180.0;
    return {float(std::sin(t) * std::cos(p)), float(std::sin(t) * std::sin(p)), float(std::cos(t))};
}

// The integral of f(w) over the upper hemisphere, by the midpoint rule in (cos theta, phi).
template <class F>
double over_hemisphere(F f) {
    constexpr int kZ = 400, kPhi = 400;
    double sum = 0.0;
    for (int i = 0; i < kZ; ++i) {
        const double z = (i + 0.5) / kZ, r = std::sqrt(1.0 - z * z);
        for (int j = 0; j < kPhi; ++j) {
            const double phi = 2.0 * npf::kPiD * (j + 0.5) / kPhi;
            sum += f(Vec3{float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)});
        }
    }
    return sum * (1.0 / kZ) * (2.0 * npf::kPiD / kPhi);
}

TEST(DirectionConvention, TheClosureWeightsByTheLightsCosine) {
    const NpfModel model = mostly_diffuse();
    const NpfClosure closure(model);
    const Vec3 view = at(15, 0), light = at(70, 180);  // cosines 0.966 and 0.342
    std::vector<float> value(closure.channel_count());
    closure.eval(view, light, WavelengthRequest::stored(), value.data());
    NpfModel::Lookup lookup;
    ASSERT_TRUE(model.prepare(/*wi=*/view, /*wo=*/light, lookup));
    for (std::size_t c = 0; c < value.size(); ++c) {
        const double f = model.value(lookup, c);
        ASSERT_GT(f, 0.0);
        EXPECT_NEAR(value[c], f * light.z, 1e-5 * f) << "channel " << c;
        EXPECT_GT(std::fabs(value[c] - f * view.z), 0.5 * f * light.z) << "weighted by the view's cosine";
    }
}

TEST(DirectionConvention, TheClosureSamplesTheLight) {
    const NpfClosure closure(mostly_diffuse());
    ASSERT_GT(closure.diffuse_probability(), 0.5);
    // Over the light it draws, the density integrates to one; over the view, to about
    // 2 cos(theta_light) times the diffuse share: far from it for a grazing fixed direction.
    const Vec3 high = at(10, 0), low = at(75, 90);
    const double over_light = over_hemisphere([&](const Vec3& light) { return closure.pdf(high, light); });
    EXPECT_GT(over_light, 0.97);
    EXPECT_LT(over_light, 1.005);
    const double over_view = over_hemisphere([&](const Vec3& view) { return closure.pdf(view, low); });
    EXPECT_LT(over_view, 0.8) << "the density does not tell the view from the light";
    // A sample is a light direction with the density of (view, light), to the bit.
    ClosureSample s;
    int drawn = 0;
    for (int k = 0; k < 64; ++k) {
        if (!closure.sample_direction(low, (k + 0.5f) / 64.f, std::fmod(k * 0.618034f, 1.f), s)) continue;
        ++drawn;
        EXPECT_EQ(s.pdf, closure.pdf(low, s.light));
    }
    EXPECT_GT(drawn, 32);
}

// npf::Brdf's (wi, wo) is the closure's (view, light): eval_cos is f cos(theta_wo), sample draws
// wo with the closure's density of (wi, wo).
TEST(DirectionConvention, TheBrdfAdapterPassesWiAsTheView) {
    const NpfModel model = mostly_diffuse();
    const NpfBrdf brdf(model);
    const NpfClosure closure(model);
    const Vec3 wi = at(20, 30), wo = at(72, 200);
    const npf::ChannelQuery q = brdf.native_query();
    std::vector<float> mine(q.size()), theirs(closure.channel_count());
    brdf.eval_cos(wi, wo, q, mine.data());
    closure.eval(/*view=*/wi, /*light=*/wo, WavelengthRequest::stored(), theirs.data());
    NpfModel::Lookup lookup;
    ASSERT_TRUE(model.prepare(wi, wo, lookup));
    for (std::size_t c = 0; c < mine.size(); ++c) {
        EXPECT_EQ(mine[c], theirs[c]);
        EXPECT_NEAR(mine[c], model.value(lookup, c) * wo.z, 1e-5 * model.value(lookup, c));
    }
    EXPECT_EQ(brdf.pdf(wi, wo), closure.pdf(wi, wo));
    EXPECT_NE(brdf.pdf(wi, wo), closure.pdf(wo, wi));
    npf::BrdfSample s;
    ClosureSample c;
    std::vector<float> weight(q.size());
    ASSERT_TRUE(brdf.sample(wi, npf::Vec2{0.3f, 0.2f}, q, s, weight.data()));
    ASSERT_TRUE(closure.sample_direction(wi, 0.3f, 0.2f, c));
    EXPECT_EQ(s.wo.x, c.light.x);
    EXPECT_EQ(s.wo.y, c.light.y);
    EXPECT_EQ(s.wo.z, c.light.z);
    EXPECT_EQ(s.pdf, brdf.pdf(wi, s.wo));
}

}  // namespace
