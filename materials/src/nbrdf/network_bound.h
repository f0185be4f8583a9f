// An upper bound of a Neural BRDF network's f_r cos(theta_i) cos(theta_o) over every direction
// pair (brdf.h's value bound), by interval arithmetic through the network over boxes of
// (theta_h, theta_d, phi_d), branch and bound; with it, bounds of every activation and output,
// so that the loader can refuse a network whose float evaluation could overflow.
#pragma once

namespace npf::nbrdf {

inline constexpr int kLayerCount = 3;

struct LayerView {
    const float* kernel;  // inputs x stride, row-major
    const float* bias;
    int inputs, units, stride;
};

// Largest |activation| accepted: sums of up to 257 terms each below it stay far from float's
// 3.4e38, so the float forward pass cannot overflow on the way.
inline constexpr double kMaxActivation = 1e30;
// Largest output x accepted: expm1f(x) below float's largest value.
inline constexpr double kMaxOutput = 88.0;

struct NetworkBound {
    double value = 0, activation = 0, output = 0;
    int boxes = 0;
};

NetworkBound bound_network(const LayerView (&layers)[kLayerCount]);

}  // namespace npf::nbrdf
