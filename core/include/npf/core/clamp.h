// Clamps for hot paths. std::fmin/std::fmax are library calls unless the compiler may assume
// finite math; these compile to single min/max instructions. A NaN argument maps to the lower
// bound, so a bad value can never escape a clamp.
#pragma once

namespace npf {

inline float clamp_low(float v, float lo) { return v > lo ? v : lo; }
inline float clamp_range(float v, float lo, float hi) { return v > lo ? (v < hi ? v : hi) : lo; }
inline double clamp_low(double v, double lo) { return v > lo ? v : lo; }
inline double clamp_range(double v, double lo, double hi) { return v > lo ? (v < hi ? v : hi) : lo; }

}  // namespace npf
