// Small float images for the image metric tests (test_image_metrics.cpp, test_heatmap.cpp,
// test_noise_floor.cpp): any picture by a function of the pixel, constants, HDR noise, scaled
// and permuted copies, and the PSNR a display difference gives.
#pragma once

#include <npf/color/display_image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <random>
#include <vector>

namespace npf::testing::images {

using npf::color::FloatImage;

inline FloatImage make_image(std::size_t width, std::size_t height, int channels,
                      const std::function<std::array<float, 4>(std::size_t, std::size_t)>& pixel) {
    FloatImage image;
    image.width = width;
    image.height = height;
    image.channels = channels;
    for (std::size_t y = 0; y < height; ++y)
        for (std::size_t x = 0; x < width; ++x) {
            const std::array<float, 4> p = pixel(x, y);
            image.pixels.insert(image.pixels.end(), p.begin(), p.begin() + channels);
        }
    return image;
}

inline FloatImage constant_image(std::size_t width, std::size_t height, float value) {
    return make_image(width, height, 3, [&](std::size_t, std::size_t) { return std::array<float, 4>{value, value, value, 1.f}; });
}

// HDR noise around a smooth gradient, values in about [-0.05, 3].
inline FloatImage noise_image(std::size_t width, std::size_t height, unsigned seed, float amplitude = 0.2f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    return make_image(width, height, 3, [&](std::size_t x, std::size_t y) {
        const float base = 0.02f + 2.5f * float(x + y) / float(width + height);
        return std::array<float, 4>{base + amplitude * (u(rng) - 0.25f), 0.5f * base + amplitude * u(rng),
                                    0.1f + amplitude * u(rng), 1.f};
    });
}

inline FloatImage scaled(const FloatImage& image, float k) {
    FloatImage out = image;
    for (std::size_t i = 0; i < out.pixels.size(); ++i)
        if (out.channels == 3 || i % 4 != 3) out.pixels[i] *= k;
    return out;
}

inline FloatImage permuted(const FloatImage& image, const std::vector<std::size_t>& order) {
    FloatImage out = image;
    const std::size_t nc = std::size_t(image.channels);
    for (std::size_t i = 0; i < order.size(); ++i)
        std::copy_n(&image.pixels[order[i] * nc], nc, &out.pixels[i * nc]);
    return out;
}

inline double psnr_of(double display_difference, double fraction = 1.0) {
    return -10.0 * std::log10(display_difference * display_difference * fraction);
}

}  // namespace npf::testing::images
