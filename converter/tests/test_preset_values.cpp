// The presets as data (issue 36): each preset's resolved ConvertSettings, every field, for an
// isotropic and an anisotropic source, pinned as the code gave them before the presets became
// key=value lines, and the canonical text they give (convert_settings_canonical_text).
#include "run_tool.h"

#include <npf/converter/convert.h>
#include <npf/converter/convert_settings_table.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace {

using namespace npf;

std::string g17(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}
std::string grid(const DetailGrid& g) { return std::to_string(g.theta_h) + "x" + std::to_string(g.theta_d) + "x" + std::to_string(g.phi_d); }

// Every field of the settings, one "name=value" a line.
std::string every_field(const ConvertSettings& s) {
    const AwlsOptions& o = s.fit;
    std::string t;
    const auto line = [&](const char* name, const std::string& value) { t += std::string(name) + "=" + value + "\n"; };
    line("fit.grid", std::to_string(o.grid.theta_h) + "," + std::to_string(o.grid.phi_h) + "," + std::to_string(o.grid.theta_d) + "," +
                         std::to_string(o.grid.phi_d));
    line("fit.g", std::to_string(o.g_theta) + "," + std::to_string(o.g_phi));
    line("fit.channels", o.channels.is_rgb() ? "rgb" : std::to_string(o.channels.size()));
    line("fit.phi_d_samples", std::to_string(o.phi_d_samples));
    line("fit.volume_weight", std::to_string(int(o.volume_weight)));
    line("fit.importance", g17(o.importance_power_view) + "," + g17(o.importance_power_light));
    line("fit.compressive", g17(o.compressive_power) + "," + g17(o.compressive_epsilon));
    line("fit.acceleration", std::to_string(int(o.acceleration)));
    line("fit.g_pin", g17(o.g_pin));
    line("fit.smith_start", std::to_string(o.smith_start) + "," + std::to_string(o.bound_g));
    line("fit.iterations", std::to_string(o.max_iterations) + "," + g17(o.tolerance) + "," + std::to_string(o.threads));
    const CompressionOptions& c = s.compression;
    line("compression", g17(c.d_ratio) + "," + g17(c.g_ratio) + "," + std::to_string(c.d_rank) + "," + std::to_string(c.g_rank) + "," +
                            std::to_string(c.per_channel));
    const DetailOptions& d = s.detail;
    std::string views;
    for (double v : d.energy_views_deg) views += g17(v) + ",";
    line("detail.grid", grid(d.grid));
    line("detail.samples", std::to_string(d.samples_per_cell) + "," + std::to_string(d.phi_h_samples));
    line("detail.display", g17(d.display_power) + "," + g17(d.display_epsilon) + "," + std::to_string(int(d.measure)));
    line("detail.clamp_passes", std::to_string(d.clamp_passes));
    line("detail.energy", g17(d.energy_weight) + ";" + views);
    line("detail.solve", g17(d.smoothness) + "," + g17(d.ratio) + "," + std::to_string(d.rank) + "," + std::to_string(d.half_precision) +
                             "," + std::to_string(d.max_iterations) + "," + g17(d.tolerance) + "," + std::to_string(d.threads));
    line("close_horizon", std::to_string(s.close_horizon));
    line("detail_only_if_better", std::to_string(s.detail_only_if_better));
    line("compress_rgb", std::to_string(s.compress_rgb));
    line("wavelengths", s.wavelengths + "," + std::to_string(s.max_wavelengths));
    line("isotropy", std::to_string(int(s.isotropy)));
    line("error", std::to_string(s.error_pairs) + "," + std::to_string(s.energy_error_samples));
    line("preset", convert_preset_name(s.preset));
    const PsnrPredictionOptions& p = s.prediction;
    std::string lightings;
    for (const std::string& l : p.lightings) lightings += l + ",";
    line("prediction", std::to_string(s.predict_psnr) + "," + std::to_string(p.size) + "," + std::to_string(p.spp) + "," +
                           std::to_string(p.seed) + "," + std::to_string(p.noise_floor) + "," + std::to_string(p.threads) + ";" +
                           lightings);
    std::string ladder;
    for (const DetailGrid& g : s.target_ladder) ladder += grid(g) + ",";
    line("target", g17(s.target_psnr) + ";" + ladder);
    return t;
}

// The production preset's for an isotropic source; each preset's lines that differ from it, and
// its anisotropic lines that differ from its isotropic ones.
struct Pinned {
    const char* preset;
    const char* isotropic;
    const char* anisotropic;
};

// `text` with each line of `differences` in place of the line of the same name.
std::string with_differences(const std::string& text, const std::string& differences) {
    std::string out;
    for (const std::string& line : npf::testing::lines_of(text)) {
        std::string kept = line;
        for (const std::string& d : npf::testing::lines_of(differences)) {
            if (d.substr(0, d.find('=')) == line.substr(0, line.find('='))) kept = d;
        }
        out += kept + "\n";
    }
    return out;
}

// every_field(preset_settings(...)) from the code before the presets were data (e6ee40a).
const char* const kProductionIsotropicFields =
    "fit.grid=90,1,90,180\n"
    "fit.g=90,1\n"
    "fit.channels=rgb\n"
    "fit.phi_d_samples=0\n"
    "fit.volume_weight=0\n"
    "fit.importance=2,2\n"
    "fit.compressive=1,0.01\n"
    "fit.acceleration=2\n"
    "fit.g_pin=0.01\n"
    "fit.smith_start=1,0\n"
    "fit.iterations=200,1.0000000000000001e-05,0\n"
    "compression=0.98999999999999999,0.98999999999999999,0,0,1\n"
    "detail.grid=32x24x16\n"
    "detail.samples=3,8\n"
    "detail.display=0.40000000000000002,0.01,1\n"
    "detail.clamp_passes=8\n"
    "detail.energy=10000;0,10,20,30,40,50,60,65,70,75,80,\n"
    "detail.solve=0.0001,0.99999000000000005,0,1,2000,9.9999999999999995e-08,0\n"
    "close_horizon=1\n"
    "detail_only_if_better=1\n"
    "compress_rgb=0\n"
    "wavelengths=,0\n"
    "isotropy=0\n"
    "error=20000,160\n"
    "preset=production\n"
    "prediction=1,128,64,1,1,0;studio,key-rim,directional,\n"
    "target=0;16x8x16,24x10x24,32x24x16,40x20x40,48x24x48,64x32x64,\n";
const Pinned kFieldsBefore[] = {
    {"preview",
     "fit.grid=45,1,45,90\n"
     "fit.g=45,1\n"
     "fit.iterations=60,0.0001,0\n"
     "detail.grid=16x8x16\n"
     "detail.display=0.40000000000000002,0.01,0\n"
     "wavelengths=,32\n"
     "error=5000,96\n"
     "preset=preview\n"
     "prediction=1,64,32,1,1,0;studio,key-rim,directional,\n",
     "fit.grid=32,64,32,64\n"
     "fit.g=32,64\n"
     "fit.phi_d_samples=8\n"},
    {"production",
     "",
     "fit.grid=90,180,90,180\n"
     "fit.g=90,180\n"
     "fit.phi_d_samples=4\n"},
    {"fine",
     "detail.grid=40x20x40\n"
     "preset=fine\n",
     "fit.grid=90,180,90,180\n"
     "fit.g=90,180\n"
     "fit.phi_d_samples=8\n"},
    {"paper",
     "fit.acceleration=1\n"
     "fit.g_pin=0\n"
     "fit.iterations=500,9.9999999999999995e-07,0\n"
     "compression=0.98999999999999999,0.98999999999999999,0,0,0\n"
     "detail.grid=0x0x0\n"
     "close_horizon=0\n"
     "preset=paper\n"
     "prediction=1,128,64,1,1,0;studio,\n",
     "fit.grid=90,180,90,180\n"
     "fit.g=90,180\n"
     "fit.phi_d_samples=16\n"},
};

// convert_settings_canonical_text(preset_settings(...)): every row's line, sorted by key.
const char* const kProductionIsotropicCanonical =
    "acceleration=anderson\n"
    "compress_rgb=false\n"
    "compressive=1\n"
    "detail=32,24,16\n"
    "detail_clamp_passes=8\n"
    "detail_energy=10000\n"
    "detail_measure=half-angle\n"
    "detail_views=0,10,20,30,40,50,60,65,70,75,80\n"
    "detail_weight=0.40000000000000002\n"
    "energy_error_samples=160\n"
    "epsilon=0.01\n"
    "error_pairs=20000\n"
    "g_grid=90,1\n"
    "g_pin=0.01\n"
    "g_prior=smith-start\n"
    "grid=90,1,90,180\n"
    "horizon=closed\n"
    "importance=2\n"
    "isotropy=auto\n"
    "iterations=200\n"
    "light=studio,key-rim,directional\n"
    "max_wavelengths=0\n"
    "no_predict=false\n"
    "pca=0.98999999999999999,0.98999999999999999\n"
    "pca_rule=per-channel\n"
    "phi_d_samples=0\n"
    "plain=false\n"
    "prediction_size=128\n"
    "prediction_spp=64\n"
    "preset=production\n"
    "rank=0,0\n"
    "target_grids=16x8x16,24x10x24,32x24x16,40x20x40,48x24x48,64x32x64\n"
    "target_psnr=0\n"
    "threads=0\n"
    "tolerance=1.0000000000000001e-05\n"
    "volume_weight=paper\n"
    "wavelengths=\n";
const Pinned kCanonical[] = {
    {"preview",
     "detail=16,8,16\n"
     "detail_measure=solid-angle\n"
     "energy_error_samples=96\n"
     "error_pairs=5000\n"
     "g_grid=45,1\n"
     "grid=45,1,45,90\n"
     "iterations=60\n"
     "max_wavelengths=32\n"
     "prediction_size=64\n"
     "prediction_spp=32\n"
     "preset=preview\n"
     "tolerance=0.0001\n",
     "g_grid=32,64\n"
     "grid=32,64,32,64\n"
     "phi_d_samples=8\n"},
    {"production",
     "",
     "g_grid=90,180\n"
     "grid=90,180,90,180\n"
     "phi_d_samples=4\n"},
    {"fine",
     "detail=40,20,40\n"
     "preset=fine\n",
     "g_grid=90,180\n"
     "grid=90,180,90,180\n"
     "phi_d_samples=8\n"},
    {"paper",
     "acceleration=line-search\n"
     "detail=none\n"
     "g_pin=0\n"
     "horizon=open\n"
     "iterations=500\n"
     "light=studio\n"
     "pca_rule=total\n"
     "preset=paper\n"
     "tolerance=9.9999999999999995e-07\n",
     "g_grid=90,180\n"
     "grid=90,180,90,180\n"
     "phi_d_samples=16\n"},
};

// For each preset and isotropy: what `text` gives, and what the pins say.
void expect_pinned(const Pinned (&pins)[4], const char* production, std::string (*text)(const ConvertSettings&)) {
    for (const Pinned& p : pins) {
        const std::string isotropic = with_differences(production, p.isotropic);
        const ConvertPreset preset = parse_convert_preset(p.preset, "preset");
        EXPECT_EQ(text(preset_settings(preset, true)), isotropic) << p.preset << " isotropic";
        EXPECT_EQ(text(preset_settings(preset, false)), with_differences(isotropic, p.anisotropic)) << p.preset << " anisotropic";
    }
}

std::string canonical_text(const ConvertSettings& s) { return convert_settings_canonical_text(s); }

TEST(PresetValues, EveryPresetResolvesAsBefore) { expect_pinned(kFieldsBefore, kProductionIsotropicFields, every_field); }

TEST(PresetValues, CanonicalTextOfEveryPreset) { expect_pinned(kCanonical, kProductionIsotropicCanonical, canonical_text); }

}  // namespace
