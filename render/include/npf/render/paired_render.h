// The paired render comparison (docs/metrics.md sec. 5), one implementation for `npf convert`'s
// PSNR prediction and the batch's validation renders: a reference material and a test material
// rendered in the Sphere scene under one lighting with environment sampling only and the same
// seed, so that both are estimated at the same light directions and most seed noise cancels in
// their difference; the pair again at noise_floor_seed(seed) for the paired noise floor.
// Directional lightings are evaluated once at pixel centres: no samples, no noise, no floor.
#pragma once

#include <npf/core/brdf.h>
#include <npf/render/image_metrics.h>
#include <npf/render/lighting.h>
#include <npf/render/path_tracer.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace npf::render {

struct PairedRenderSettings {
    std::size_t size = 128;   // image width and height, pixels
    std::uint32_t spp = 64;   // samples per pixel, times the lighting's spp_factor
    std::uint64_t seed = 1;   // the pair's seed; the floor's is noise_floor_seed(seed)
    unsigned threads = 0;     // 0: all cores (the images do not depend on it)
    bool noise_floor = true;  // false: no second pair (half the cost), floor_psnr 0
    // The two images as errors name them.
    std::string reference_name = "reference", test_name = "test";
};

// The options one image of a pair is rendered with at `seed`.
RenderOptions paired_render_options(const PairedRenderSettings& settings, const Lighting& lighting, std::uint64_t seed);

// One test material's side of a pair and its figures against the reference.
struct PairedComparison {
    RenderResult test;     // the test material at the seed
    ImageMetrics metrics;  // its PSNR, SSIM, relMSE against the reference
    // dB, the paired noise floor: +infinity for a directional lighting (two renders differ only by
    // their materials), 0 when not measured (no floor asked for).
    double floor_psnr = 0.0;
    bool noise_limited = false;  // render::noise_limited: half or more of the MSE is seed noise
};

// The reference side, rendered once (at the seed, and at the floor's seed when there is a floor
// and noise), so that any number of test materials can be compared with it (the --target-psnr
// ladder renders its source once).
class PairedReference {
public:
    PairedReference(const Brdf& reference, Lighting lighting, PairedRenderSettings settings);

    // Renders `test` at the seed (and at the floor's seed when `with_floor` and the settings ask
    // for a floor) and compares it with the reference.
    PairedComparison compare(const Brdf& test, bool with_floor = true) const;

    const RenderResult& reference() const { return m_reference; }
    const Lighting& lighting() const { return m_lighting; }
    const PairedRenderSettings& settings() const { return m_settings; }
    // The options of the images at the seed (both the reference's and the test's).
    RenderOptions options() const { return paired_render_options(m_settings, m_lighting, m_settings.seed); }

private:
    Lighting m_lighting;
    PairedRenderSettings m_settings;
    RenderResult m_reference;
    std::optional<RenderResult> m_reference_floor;  // at noise_floor_seed, when measured
};

}  // namespace npf::render
