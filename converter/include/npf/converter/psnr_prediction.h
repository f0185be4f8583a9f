// What a conversion will score in a paired render comparison, predicted cheaply at convert time:
// the source and the conversion rendered in the Sphere scene under the environment map with
// environment sampling only and the same seed (both estimated at the same light directions, so
// most seed noise cancels in their difference), compared by npf compare's PSNR
// (npf/render/image_metrics.h). The full comparison it predicts is docs/fitting.md's:
//   npf render X -o x.exr --spp 128 --seed 1 --sampling env   (256 x 256), for both, then
//   npf compare raw.exr conv.exr
// The defaults below are smaller (the render's cost is what matters at convert time); their
// agreement with the full figure on the five real materials is measured in docs/metrics.md
// ("Predicted at convert time").
#pragma once

#include <npf/color/display_image.h>
#include <npf/core/brdf.h>
#include <npf/render/environment_map.h>
#include <npf/shading/npf_model.h>

#include <cstdint>
#include <string>

namespace npf {

struct PsnrPredictionOptions {
    // 128 x 128 at 64 spp came within 0.45 dB of the full comparison on the five real materials;
    // 64 x 64 (a quarter of the cost) within 1.5 dB, 128 x 32 within 1.2 dB (docs/metrics.md).
    std::size_t size = 128;        // image width and height, pixels
    std::uint32_t spp = 64;        // samples per pixel
    std::uint64_t seed = 1;        // the full comparison's seed
    // The paired noise floor (render::paired_noise_floor): the same pair at this second seed,
    // which doubles the cost of a prediction; 0 skips it.
    std::uint64_t floor_seed = 2;
    std::string environment;       // lat-long map; empty: the shipped one (default_environment.h)
    int threads = 0;               // 0: all cores
};

struct PsnrPrediction {
    double psnr = 0.0;        // dB; +infinity when the renders agree exactly
    double floor_psnr = 0.0;  // dB, the paired noise floor; 0 when not measured
    bool noise_limited = false;  // render::noise_limited: half or more of the MSE is seed noise
    double seconds = 0.0;     // rendering and comparing the conversion (the source's renders not counted)
};

// Renders the source once (at the seed, and at the floor's seed when there is one) so that any
// number of conversions can be predicted against it (the --target-psnr ladder). Throws
// npf::Error for bad options, a missing or unreadable environment map, or a material the render
// cannot query.
class PsnrPredictor {
public:
    PsnrPredictor(const Brdf& source, const PsnrPredictionOptions& options = {});

    // The conversion against the source; with_floor also renders it at the floor's seed (when
    // the options have one).
    PsnrPrediction predict(const Brdf& conversion, bool with_floor = true) const;
    PsnrPrediction predict(const NpfModel& conversion, bool with_floor = true) const;

    const PsnrPredictionOptions& options() const { return m_options; }
    // The render settings in words, for summaries and metadata:
    // "Sphere 128x128, 64 spp, env sampling, seed 1 (floor: seed 2), studio.exr".
    std::string settings_text() const;
    double source_seconds() const { return m_source_seconds; }  // the source's renders

private:
    color::FloatImage render_at(const Brdf& material, std::uint64_t seed) const;

    PsnrPredictionOptions m_options;
    render::EnvironmentMap m_environment;
    color::FloatImage m_source, m_source_floor;
    double m_source_seconds = 0.0;
};

}  // namespace npf
