// Two materials compared in BRDF space at direction pairs (issue 34: BRDF-space accuracy as a
// first-class figure, beside the renders): the relative RMS of f_r cos(theta_o) over the pairs with
// both directions within a cap (80 degrees by default: the measurements are least reliable beyond),
// every channel pooled,
//   sqrt(sum (test - reference)^2 / sum reference^2),
// per channel, again within 60 degrees (where a glossy grazing peak no longer counts), and the
// largest difference with its pair: where a peak is too high or too low.
#pragma once

#include <npf/core/brdf.h>
#include <npf/core/vec.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace npf {

struct DirectionPair {
    Vec3 wi, wo;
};

struct BrdfComparisonResult {
    std::size_t pairs = 0;       // given
    std::size_t used = 0;        // with both directions within the cap
    double relative_rms = 0.0;   // pooled over channels
    std::vector<double> channel_relative_rms;
    double relative_rms_60 = 0.0;  // pooled, both directions within 60 degrees
    // The largest |test - reference| of f_r cos(theta_o) among the used pairs and channels.
    struct Worst {
        std::size_t pair = 0;     // index among the given pairs, from 0
        std::size_t channel = 0;
        double test = 0.0, reference = 0.0;
        Vec3 wi, wo;
    } worst;
};

// Accumulates pairs one at a time (a stream of any length costs nothing per pair).
class BrdfComparison {
public:
    explicit BrdfComparison(std::size_t channels, double max_theta_degrees = 80.0);
    // The values of f_r cos(theta_o) of every channel at the pair.
    void add(const Vec3& wi, const Vec3& wo, const float* test, const float* reference);
    BrdfComparisonResult result() const;

private:
    std::size_t m_channels;
    double m_min_cos, m_min_cos_60;
    std::size_t m_pairs = 0, m_used = 0;
    std::vector<double> m_num, m_den;
    double m_num_60 = 0.0, m_den_60 = 0.0;
    BrdfComparisonResult::Worst m_worst;
    double m_worst_difference = -1.0;
};

// Both materials at `pairs`, every channel of `channels` (each must provide them: npf::Error);
// negative values clamped to 0 as evaluation does by default, or kept (npf eval --raw).
BrdfComparisonResult compare_brdfs(const Brdf& test, const Brdf& reference, const Channels& channels,
                                   const std::vector<DirectionPair>& pairs, double max_theta_degrees = 80.0,
                                   bool keep_negative = false);
// The same at each pair `next` writes until it returns false: a stream of any length.
BrdfComparisonResult compare_brdfs(const Brdf& test, const Brdf& reference, const Channels& channels,
                                   const std::function<bool(DirectionPair&)>& next, double max_theta_degrees = 80.0,
                                   bool keep_negative = false);

// The held-out pairs npf convert measures a conversion at, fixed once for all (the same on every
// machine: no library random distribution): 500 pairs with both directions within 80 degrees,
// 100 mirror pairs and 100 within 10 degrees of the mirror direction (where glossy peaks are, at
// incidences up to 80 degrees), and 300 drawn cosine-weighted on the cap.
std::vector<DirectionPair> held_out_pairs();

}  // namespace npf
