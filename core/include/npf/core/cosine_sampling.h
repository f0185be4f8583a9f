// Cosine-weighted hemisphere sampling, for sources without a better sampler of their own
// (MERL files, NPF textures until the alias-table sampler): pdf(wo) = cos(theta_o) / pi.
#pragma once

#include <npf/core/brdf.h>

namespace npf {

// Shirley-Chiu concentric map of u onto the unit disk, lifted to the hemisphere; z may be 0
// on the disk's rim.
Vec3 cosine_hemisphere_direction(const Vec2& u);

// Brdf::sample for a source whose pdf is the cosine density: draws wo, fills s and, when
// `weight` is not null, f_r cos / pdf from source.eval_cos. Same contract as Brdf::sample.
bool sample_cosine_hemisphere(const Brdf& source, const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                              float* weight);

}  // namespace npf
