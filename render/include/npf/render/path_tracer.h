// The Sphere scene renderer: direct lighting of a material on the unit sphere by the
// environment map, with multiple importance sampling, deterministic for a given seed.
//
// A convex sphere lit only by a distant environment has no interreflection and no shadowing
// other than its own horizon, so direct lighting is the exact solution and one bounce is the
// whole path: per camera sample, one environment sample and one BSDF sample (Brdf::sample),
// combined with the power heuristic (Veach 1997, beta = 2):
//     L += f cos(theta_o) L_env(wo) w_env / p_env       w_env  = p_env^2 / (p_env^2 + p_brdf^2)
//     L += weight_brdf L_env(wo') w_brdf                 w_brdf = p_brdf^2 / (p_env^2 + p_brdf^2)
// with p_brdf = Brdf::pdf(wi, wo) for the environment's direction and Brdf::sample's pdf for its
// own. The camera-side direction is the Brdf's `wi`, the light direction its `wo`.
//
// Pixels: the average of `spp` samples at points spread over the pixel (a box filter);
// samples that miss the sphere contribute 0 and no coverage, so alpha is the covered fraction
// and the colour is premultiplied by it (OpenEXR's convention): the silhouette is antialiased
// and the background is (0, 0, 0, 0).
//
// Determinism and shared random numbers: every random number comes from
// (seed, pixel, sample, dimension) (rng.h): pair 0 places the sample in the pixel, pair 1 is
// the environment sample, pair 2 the BSDF sample, whether or not they are used. Each pixel is
// computed by one thread, in sample order, into its own slot, so the image is bit-identical
// for any thread count; and two materials rendered with the same seed see the same camera rays
// and the same environment samples (docs/render.md).
#pragma once

#include <npf/color/display_image.h>
#include <npf/core/brdf.h>
#include <npf/core/channels.h>
#include <npf/render/environment_map.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace npf::render {

enum class SceneKind { Sphere };

// Which light-transport estimator: both strategies combined (the default), or one alone, which
// is unbiased too but noisier; comparing them checks the MIS weights and judges convergence.
enum class Sampling {
    Mis,          // one environment and one BSDF sample, power heuristic
    Brdf,         // BSDF samples only (Brdf::sample), weight 1
    Environment,  // environment samples only, weight 1
};

struct RenderOptions {
    // The renderer's bounds (render() refuses others; `npf render` and the batch's render.*
    // settings take theirs from here).
    static constexpr std::size_t kMaxSide = 16384;             // pixels, width and height
    static constexpr std::uint32_t kMaxSpp = std::uint32_t(1) << 24;

    SceneKind scene = SceneKind::Sphere;
    std::size_t width = 256, height = 256;  // 1 .. kMaxSide each
    std::uint32_t spp = 64;                  // samples per pixel, 1 .. kMaxSpp
    std::uint64_t seed = 0;
    unsigned threads = 0;                    // 0: npf::thread_count(0) (all hardware threads)
    // Nothing: as the material stores (RGB, or the default wavelength quadrature,
    // render_channels.h). Channels::rgb() or a wavelength list to override.
    std::optional<Channels> channels;
    Sampling sampling = Sampling::Mis;
    // Negative (out-of-gamut) values of a measured file: clamped to 0 (false, as the RGL group's
    // loader and npf's readers evaluate) or kept as stored (true, as Mitsuba's `measured` renders).
    bool keep_negative = false;
};

struct RenderStats {
    double seconds = 0.0;               // wall-clock time of render() (setup included)
    std::uint64_t camera_samples = 0;   // width * height * spp
    std::uint64_t hit_samples = 0;      // camera samples that hit the sphere
    std::uint64_t dropped_values = 0;   // non-finite contributions discarded (material bugs)
    unsigned threads = 0;               // threads used
};

struct RenderResult {
    // Premultiplied linear Rec.709 RGBA (4 channels), rows top to bottom.
    color::FloatImage image;
    Channels channels;  // what the material was evaluated at (RGB or the quadrature wavelengths)
    RenderStats stats;

    // A black, transparent image of the options' size, to be filled: one layout for every way
    // of rendering (path tracing, delta lights).
    static RenderResult blank(const Channels& channels, std::size_t width, std::size_t height) {
        RenderResult r;
        r.channels = channels;
        r.image.width = width;
        r.image.height = height;
        r.image.channels = 4;
        r.image.pixels.assign(width * height * 4, 0.f);
        return r;
    }
};

// Called with the fraction of rows done (0 .. 1), from the render's threads one at a time.
using RenderProgress = std::function<void(double)>;

// Throws npf::Error ("render options") for options out of range, and what Brdf::query throws
// when the material cannot provide the channels (e.g. wavelengths from an RGB material).
void validate_render_options(const RenderOptions& options);

RenderResult render(const Brdf& material, const EnvironmentMap& environment, const RenderOptions& options,
                    const RenderProgress& progress = {});

}  // namespace npf::render
