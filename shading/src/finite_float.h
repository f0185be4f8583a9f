// The closure's outputs as floats: finite always (a grazing view can push f_r cos / pdf past
// float's range; NaN becomes 0). Shared by the scalar and the batched closure.
#pragma once

#include <algorithm>
#include <limits>

namespace npf {

inline float finite_float(double v) {
    constexpr double kMax = std::numeric_limits<float>::max();
    if (!(v == v)) return 0.f;
    return float(std::clamp(v, -kMax, kMax));
}

}  // namespace npf
