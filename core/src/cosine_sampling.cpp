#include <npf/core/cosine_sampling.h>

#include <algorithm>
#include <cmath>

namespace npf {

Vec3 cosine_hemisphere_direction(const Vec2& u) {
    const float a = 2.f * u.x - 1.f, b = 2.f * u.y - 1.f;
    float r = 0.f, phi = 0.f;
    if (a != 0.f || b != 0.f) {
        if (std::fabs(a) > std::fabs(b)) {
            r = a;
            phi = (kPi / 4.f) * (b / a);
        } else {
            r = b;
            phi = (kPi / 2.f) - (kPi / 4.f) * (a / b);
        }
    }
    const float z = std::sqrt(std::max(0.f, 1.f - r * r));
    return Vec3{r * std::cos(phi), r * std::sin(phi), z};
}

bool sample_cosine_hemisphere(const Brdf& source, const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                              float* weight) {
    const std::size_t n = query.size();
    if (weight) std::fill(weight, weight + n, 0.f);
    if (!(wi.z > 0.f)) return false;
    const Vec3 wo = cosine_hemisphere_direction(u);
    if (!(wo.z > 0.f)) return false;
    const float p = source.pdf(wi, wo);
    if (!(p > 0.f)) return false;
    s.wo = wo;
    s.pdf = p;
    if (weight) {
        source.eval_cos(wi, wo, query, weight);
        for (std::size_t k = 0; k < n; ++k) weight[k] /= p;
    }
    return true;
}

}  // namespace npf
