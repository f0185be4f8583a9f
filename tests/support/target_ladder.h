// The target-PSNR tests' source, quick conversion (test_target_psnr.cpp, test_lightings.cpp)
// and the metadata they read back from the written model.
#pragma once

#include "synthetic_rgl.h"

#include <npf/converter/convert.h>
#include <npf/core/brdf.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/shading/npf_model.h>

#include <memory>
#include <string>

namespace npf::testing {

// An RGB source (a spectral one renders at its wavelengths, many times slower): a small
// synthetic RGL file, a peaked lobe over a diffuse floor, written once per process.
inline const std::string& synthetic_lobe_path() {
    static const std::string path =
        write_synthetic_rgl(SyntheticRglSpec{}, temporary_folder("target-ladder-source") + "/lobe.bsdf");
    return path;
}

// That file, read once per process.
inline const npf::Brdf& synthetic_lobe() {
    static const std::unique_ptr<npf::RglBrdf> source = npf::RglBrdf::load(synthetic_lobe_path());
    return *source;
}

// A quick production RGB fit: a coarse base (so that a detail layer has something to add), two
// threads, and a two-step target ladder predicted at a quarter of the default render (the ladder
// predicts every candidate). The error pairs and the detail grid are the test's own.
inline npf::ConvertSettings small_ladder_settings() {
    npf::ConvertSettings s = npf::preset_settings(npf::ConvertPreset::Production, true);
    s.fit.grid = {16, 1, 12, 24};
    s.fit.g_theta = 12;
    s.fit.max_iterations = 30;
    s.fit.threads = 2;
    s.target_ladder = {npf::DetailGrid{8, 4, 8}, npf::DetailGrid{16, 8, 16}};
    s.prediction.threads = 2;
    s.prediction.size = 64;
    s.prediction.spp = 16;
    return s;
}

// The model's metadata value under `key`, or "(absent)".
inline std::string metadata_value(const npf::NpfModel& m, const std::string& key) {
    for (const auto& [k, v] : m.metadata)
        if (k == key) return v;
    return "(absent)";
}

}  // namespace npf::testing
