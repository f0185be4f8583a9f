// The presets as data: each is a list of "key=value" lines, applied over ConvertSettings{}
// through the rows' own checks and `apply` (the one place a setting's text becomes a value), so
// that `npf convert --help`'s defaults (setting_default) read the same lines. The trade-offs are
// measured in docs/fitting.md.
#include "setting_rows.h"

#include <npf/core/error.h>

namespace npf {

namespace {

struct PresetLines {
    std::vector<std::string> all, isotropic, anisotropic;
};

// The paper's compression ratio (its sec. 4.1) for every preset; the grids per isotropy.
PresetLines lines_of(ConvertPreset preset) {
    switch (preset) {
    case ConvertPreset::Preview:
        // Its detail grid is too coarse to carry a sub-degree peak without costing the renders
        // elsewhere (ilm_l3_37_metallic: studio 45.2 dB per solid angle, 40.0 per half-vector
        // angle; docs/fitting.md, "Under any light"): the quick look keeps the solid-angle
        // measure. An eighth of the production prediction's renders: within 1.7 dB of the full
        // figure on the five real materials (docs/metrics.md), and its floor says when noise rules.
        return {{"preset=preview", "pca=0.99,0.99", "iterations=60", "tolerance=1e-4", "max_wavelengths=32", "error_pairs=5000",
                 "detail=16,8,16", "detail_measure=solid-angle", "horizon=closed", "prediction_size=64", "prediction_spp=32",
                 "energy_error_samples=96"},
                {"grid=45,1,45,90", "g_grid=45,1", "phi_d_samples=0"},
                {"grid=32,64,32,64", "g_grid=32,64", "phi_d_samples=8"}};
    case ConvertPreset::Production:
        // Anisotropic: 4 phi_d samples per ring (docs/fitting.md, "Issue 19, fifth step": renders
        // within 0.15 dB of 8's, 1.3 to 1.7 times faster, 1.1 to 1.3 GB less). The accuracy
        // ladder (docs/fitting.md, "Detail layer"): the same base, a finer residual.
        return {{"preset=production", "pca=0.99,0.99", "iterations=200", "tolerance=1e-5", "detail=32,24,16", "horizon=closed"},
                {"grid=90,1,90,180", "g_grid=90,1", "phi_d_samples=0"},
                {"grid=90,180,90,180", "g_grid=90,180", "phi_d_samples=4"}};
    case ConvertPreset::Fine:
        return {{"preset=fine", "pca=0.99,0.99", "iterations=200", "tolerance=1e-5", "detail=40,20,40", "horizon=closed"},
                {"grid=90,1,90,180", "g_grid=90,1", "phi_d_samples=0"},
                {"grid=90,180,90,180", "g_grid=90,180", "phi_d_samples=8"}};
    case ConvertPreset::Paper:
        // The paper's pure model, fitted as it was measured (docs/fitting.md, "Convergence"): the
        // line search without the G pin, the paper's total ratio, judged under the studio map
        // alone, so that its files stay as they were.
        return {{"preset=paper", "pca=0.99,0.99", "iterations=500", "tolerance=1e-6", "acceleration=line-search", "g_pin=0",
                 "pca_rule=total", "light=studio"},
                {"grid=90,1,90,180", "g_grid=90,1", "phi_d_samples=0"},
                {"grid=90,180,90,180", "g_grid=90,180", "phi_d_samples=16"}};
    }
    return {};
}

void apply_line(ConvertSettings& s, const std::string& line) {
    const std::size_t eq = line.find('=');
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    const ConvertSettingRow* row = find_setting(settings_rows::all_settings(), key);
    if (!row) throw Error("preset", "no setting '" + key + "'");
    row->apply(s, check_setting(*row, value, "preset " + key));
}

}  // namespace

ConvertSettings preset_settings(ConvertPreset preset, bool isotropic) {
    const PresetLines lines = lines_of(preset);
    ConvertSettings s;
    for (const std::string& line : lines.all) apply_line(s, line);
    for (const std::string& line : isotropic ? lines.isotropic : lines.anisotropic) apply_line(s, line);
    return s;
}

}  // namespace npf
