#include <npf/materials/cosine_sampled_brdf.h>

#include <npf/core/cosine_sampling.h>

namespace npf {

float CosineSampledBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
    if (!(wi.z > 0.f) || !(wo.z > 0.f)) return 0.f;
    return wo.z * (1.f / kPi);
}

bool CosineSampledBrdf::sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                               float* weight) const {
    return sample_cosine_hemisphere(*this, wi, u, query, s, weight);
}

}  // namespace npf
