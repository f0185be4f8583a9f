// What a conversion will score in a paired render comparison, predicted cheaply at convert time:
// the source and the conversion rendered in the Sphere scene under each lighting of a set
// (npf/render/lighting.h; by default studio, key-rim and directional), maps with environment
// sampling only and the same seed (both estimated at the same light directions, so most seed
// noise cancels in their difference), directional lights with no Monte Carlo at all, compared by
// npf compare's PSNR (npf/render/image_metrics.h). The prediction is the worst of the set: a soft
// map alone hides the height of glossy peaks and the grazing band, which a key and a rim show. The full comparison it predicts is docs/fitting.md's:
//   npf render X -o x.exr --spp 128 --seed 1 --sampling env   (256 x 256), for both, then
//   npf compare raw.exr conv.exr
// The defaults below are smaller (the render's cost is what matters at convert time); their
// agreement with the full figure on the five real materials is measured in docs/metrics.md
// ("Predicted at convert time").
#pragma once

#include <npf/color/display_image.h>
#include <npf/core/brdf.h>
#include <npf/render/environment_map.h>
#include <npf/render/lighting.h>
#include <npf/render/paired_render.h>
#include <npf/shading/npf_model.h>

#include <cstdint>
#include <string>
#include <vector>

namespace npf {

struct PsnrPredictionOptions {
    // 128 x 128 at 64 spp came within 0.45 dB of the full comparison on the five real materials;
    // 64 x 64 (a quarter of the cost) within 1.5 dB, 128 x 32 within 1.2 dB (docs/metrics.md).
    std::size_t size = 128;        // image width and height, pixels
    std::uint32_t spp = 64;        // samples per pixel
    std::uint64_t seed = 1;        // the full comparison's seed
    // The paired noise floor (render::paired_noise_floor): the same pair again at
    // render::noise_floor_seed(seed), which doubles the cost of a prediction; false skips it.
    bool noise_floor = true;
    // The lightings judged (render::make_lighting: built-in names or map files), each rendered
    // at spp x its own spp_factor; the prediction is their worst. `npf convert --light` replaces
    // the set: a material for a softly lit background need not be judged under a key light.
    std::vector<std::string> lightings = render::builtin_lighting_names();
    int threads = 0;               // 0: all cores
};

// One lighting's figures.
struct LightingPrediction {
    std::string lighting;        // render::Lighting::label()
    double psnr = 0.0;           // dB; +infinity when the renders agree exactly
    // dB, the paired noise floor: 0 when not measured, +infinity for a noise-free lighting
    // (directional: two renders differ only by their materials).
    double floor_psnr = 0.0;
    bool noise_limited = false;  // render::noise_limited: half or more of the MSE is seed noise
};

struct PsnrPrediction {
    double psnr = 0.0;        // dB, the worst (lowest) lighting's; +infinity when every pair agrees exactly
    double floor_psnr = 0.0;  // dB, that lighting's floor (as LightingPrediction)
    bool noise_limited = false;  // that lighting's
    std::string worst;        // that lighting's label
    std::vector<LightingPrediction> lightings;  // each, in the options' order
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
    // The render settings in words, for summaries and metadata: for one map lighting
    // "Sphere 128x128, 64 spp, env sampling, seed 1 (floor: seed 2), studio.exr" (as before sets),
    // for a set "Sphere 128x128, env sampling, seed 1 (floor: seed 2); worst of studio 64 spp,
    // key-rim 256 spp, directional at pixel centres (no noise)".
    std::string settings_text() const;

private:
    PsnrPredictionOptions m_options;
    std::vector<render::PairedReference> m_judged;  // one per lighting, the source rendered
};

}  // namespace npf
