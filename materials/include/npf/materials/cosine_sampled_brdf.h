// The base of the material files that carry no sampling data (MERL tables, Neural BRDF networks):
// their own table or network does not invert cheaply, so wo is drawn cosine-weighted over the
// hemisphere (cosine_sampling.h): exact for the diffuse part, never zero where the BRDF is not,
// and pdf and sample stay trivially consistent. A reader fills m_info and implements eval_cos.
#pragma once

#include <npf/core/brdf.h>

namespace npf {

class CosineSampledBrdf : public Brdf {
public:
    const BrdfInfo& info() const override { return m_info; }
    // cos(theta_o) / pi, 0 with either direction at or below the horizon.
    float pdf(const Vec3& wi, const Vec3& wo) const override;
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                float* weight) const override;

protected:
    CosineSampledBrdf() = default;

    BrdfInfo m_info;
};

}  // namespace npf
