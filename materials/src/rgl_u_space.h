// The u-space of the RGL tables (docs/rgl-format.md, sec. 0), shared by
// the reader and the writer so that both map angles identically: a square-root warp of the
// elevation and a linear map of the azimuth onto [0, 1]. A private header of theirs: the names
// are taken into npf for them.
#pragma once

#include <npf/core/clamp.h>
#include <npf/core/vec.h>

#include <cmath>

namespace npf::rgl {

inline float theta_to_u(float theta) { return std::sqrt(clamp_low(theta, 0.f) * (2.f / kPi)); }
inline float phi_to_u(float phi) { return (phi + kPi) * (1.f / (2.f * kPi)); }
inline float u_to_theta(float u) { return 0.5f * kPi * u * u; }
inline float u_to_phi(float u) { return (2.f * u - 1.f) * kPi; }

}  // namespace npf::rgl

namespace npf {
using rgl::phi_to_u;
using rgl::theta_to_u;
using rgl::u_to_phi;
using rgl::u_to_theta;
}  // namespace npf
