// How far a fitted model is from its source, in BRDF space: the relative RMS error of f_r over
// direction pairs drawn cosine-weighted on the cap theta < max_theta (away from grazing, where
// the measured data are least reliable and the 1/(cos cos) of the model amplifies noise):
//   relative RMS (channel c) = sqrt(sum (model_c - source_c)^2 / sum source_c^2).
// The cosine weighting of both directions is the weighting of irradiance and projected view.
#pragma once

#include <npf/core/brdf.h>

#include <functional>
#include <vector>

namespace npf {

struct BrdfSpaceError {
    std::vector<double> relative_rms;  // per channel
    double mean_relative_rms = 0.0;    // over the channels
    double max_relative_rms = 0.0;     // the worst channel
    double overall_relative_rms = 0.0; // all channels pooled
};

// model(wi, wo, out) writes f_r of every channel of `channels` (not f_r cos).
using ModelEvaluation = std::function<void(const Vec3& wi, const Vec3& wo, double* out)>;

BrdfSpaceError brdf_space_error(const Brdf& source, const Channels& channels, const ModelEvaluation& model, int pairs = 20000,
                                double max_theta_degrees = 80.0, unsigned seed = 7);

}  // namespace npf
