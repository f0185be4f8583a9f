// Anisotropic microfacet normal distributions (GGX and Beckmann) with separable Smith
// masking, in a lobe frame that may be rotated about the normal.
#pragma once

#include <npf/core/vec.h>

namespace npf {

enum class MicrofacetDistribution { Ggx, Beckmann };

struct MicrofacetNdf {
    MicrofacetDistribution type = MicrofacetDistribution::Ggx;
    float alpha_x = 0.1f;   // roughness along the lobe's tangent
    float alpha_y = 0.1f;   // roughness along the lobe's bitangent
    float rotation = 0.f;   // radians: the lobe's tangent is the surface tangent rotated towards y

    bool isotropic() const { return alpha_x == alpha_y; }

    // D(m), normalised so that integral D(m) cos(theta_m) dm = 1 over the hemisphere; 0 for
    // m.z <= 0. m in the surface frame (the rotation is applied inside).
    float eval(const Vec3& m) const;
    // Smith Lambda(w) and the masking G1(w, m) = chi(w.m) / (1 + Lambda(w)). Lambda is the
    // exact one for both (Beckmann through erfc), taken at |w.z| (symmetric), infinite at
    // w.z = 0 (so G1 = 0 there).
    float lambda(const Vec3& w) const;
    float smith_g1(const Vec3& w, const Vec3& m) const;
    // Projected area sigma(w) = integral max(0, w.m) D(m) dm = w.z (1 + Lambda(w)) for w.z > 0;
    // the closed form used is the integral itself for every w (finite, > 0 at the horizon,
    // where G1(w) / w.z = 1 / sigma(w) stays finite).
    float projected_area(const Vec3& w) const;
    // A normal m with density D(m) cos(theta_m) (solid angle) from a uniform point u.
    Vec3 sample(const Vec2& u) const;
};

}  // namespace npf
