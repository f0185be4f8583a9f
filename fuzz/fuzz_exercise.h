// What the material targets do with an input their reader accepts: evaluation, pdf and sampling
// at a few fixed direction pairs (the code paths a renderer takes right after loading).
#pragma once

#include <npf/core/brdf.h>

#include <vector>

namespace npf::fuzz {

inline void exercise(const Brdf& brdf) {
    const ChannelQuery q = brdf.native_query();
    std::vector<float> out(q.size() + 1), weight(q.size() + 1);
    const Vec3 dirs[] = {{0.f, 0.f, 1.f}, {0.6f, 0.f, 0.8f}, {0.f, -0.96f, 0.28f}, {0.99f, 0.1f, 0.01f}, {0.3f, 0.3f, -0.9f}};
    for (const Vec3& wi : dirs) {
        for (const Vec3& wo : dirs) {
            brdf.eval_cos(wi, wo, q, out.data());
            (void)brdf.pdf(wi, wo);
        }
        for (const Vec2& u : {Vec2{0.3f, 0.7f}, Vec2{0.f, 0.f}, Vec2{0.9999f, 0.5f}}) {
            BrdfSample s;
            (void)brdf.sample(wi, u, q, s, weight.data());
        }
    }
}

}  // namespace npf::fuzz
