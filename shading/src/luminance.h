// Luminance weights of a material's stored channels, summing to 1: CIE Y under the project's
// colour convention (npf/color/spectrum.h) for wavelengths, Rec. 709 for RGB, and a flat average
// when no stored wavelength is visible. What "luminance-averaged" means for the sampler.
#pragma once

#include <npf/color/spectrum.h>
#include <npf/core/channels.h>
#include <npf/core/rec709_luminance.h>

#include <algorithm>
#include <iterator>
#include <vector>

namespace npf {

inline std::vector<double> luminance_weights_of(const Channels& channels) {
    if (channels.is_rgb()) return std::vector<double>(std::begin(kRec709Luminance), std::end(kRec709Luminance));
    const std::size_t C = channels.size();
    std::vector<double> y = color::luminance_weights(channels.wavelengths());
    double sum = 0.0;
    for (double& v : y) sum += (v = std::max(v, 0.0));
    for (double& v : y) v = sum > 0.0 ? v / sum : 1.0 / double(C);
    return y;
}

}  // namespace npf
