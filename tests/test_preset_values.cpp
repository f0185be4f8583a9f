// The presets as data (issue 36): each preset's resolved ConvertSettings, every field, for an
// isotropic and an anisotropic source, pinned as the code gave them before the presets became
// key=value lines (test_preset_canonical_text.cpp pins the canonical text they give).
#include <npf/converter/convert.h>

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

struct Pinned {
    const char* preset;
    bool isotropic;
    const char* fields;
};

// every_field(preset_settings(...)) from the code before the presets were data (e6ee40a).
const Pinned kBefore[] = {
    {"preview", true, R"(fit.grid=45,1,45,90
fit.g=45,1
fit.channels=rgb
fit.phi_d_samples=0
fit.volume_weight=0
fit.importance=2,2
fit.compressive=1,0.01
fit.acceleration=2
fit.g_pin=0.01
fit.smith_start=1,0
fit.iterations=60,0.0001,0
compression=0.98999999999999999,0.98999999999999999,0,0,1
detail.grid=16x8x16
detail.samples=3,8
detail.display=0.40000000000000002,0.01,0
detail.clamp_passes=8
detail.energy=10000;0,10,20,30,40,50,60,65,70,75,80,
detail.solve=0.0001,0.99999000000000005,0,1,2000,9.9999999999999995e-08,0
close_horizon=1
detail_only_if_better=1
compress_rgb=0
wavelengths=,32
isotropy=0
error=5000,96
preset=preview
prediction=1,64,32,1,1,0;studio,key-rim,directional,
target=0;16x8x16,24x10x24,32x24x16,40x20x40,48x24x48,64x32x64,
)"},
    {"preview", false, R"(fit.grid=32,64,32,64
fit.g=32,64
fit.channels=rgb
fit.phi_d_samples=8
fit.volume_weight=0
fit.importance=2,2
fit.compressive=1,0.01
fit.acceleration=2
fit.g_pin=0.01
fit.smith_start=1,0
fit.iterations=60,0.0001,0
compression=0.98999999999999999,0.98999999999999999,0,0,1
detail.grid=16x8x16
detail.samples=3,8
detail.display=0.40000000000000002,0.01,0
detail.clamp_passes=8
detail.energy=10000;0,10,20,30,40,50,60,65,70,75,80,
detail.solve=0.0001,0.99999000000000005,0,1,2000,9.9999999999999995e-08,0
close_horizon=1
detail_only_if_better=1
compress_rgb=0
wavelengths=,32
isotropy=0
error=5000,96
preset=preview
prediction=1,64,32,1,1,0;studio,key-rim,directional,
target=0;16x8x16,24x10x24,32x24x16,40x20x40,48x24x48,64x32x64,
)"},
    {"production", true, R"(fit.grid=90,1,90,180
fit.g=90,1
fit.channels=rgb
fit.phi_d_samples=0
fit.volume_weight=0
fit.importance=2,2
fit.compressive=1,0.01
fit.acceleration=2
fit.g_pin=0.01
fit.smith_start=1,0
fit.iterations=200,1.0000000000000001e-05,0
compression=0.98999999999999999,0.98999999999999999,0,0,1
detail.grid=32x24x16
detail.samples=3,8
detail.display=0.40000000000000002,0.01,1
detail.clamp_passes=8
detail.energy=10000;0,10,20,30,40,50,60,65,70,75,80,
detail.solve=0.0001,0.99999000000000005,0,1,2000,9.9999999999999995e-08,0
close_horizon=1
detail_only_if_better=1
compress_rgb=0
wavelengths=,0
isotropy=0
error=20000,160
preset=production
prediction=1,128,64,1,1,0;studio,key-rim,directional,
target=0;16x8x16,24x10x24,32x24x16,40x20x40,48x24x48,64x32x64,
)"},
    {"production", false, R"(fit.grid=90,180,90,180
fit.g=90,180
fit.channels=rgb
fit.phi_d_samples=4
fit.volume_weight=0
fit.importance=2,2
fit.compressive=1,0.01
fit.acceleration=2
fit.g_pin=0.01
fit.smith_start=1,0
fit.iterations=200,1.0000000000000001e-05,0
compression=0.98999999999999999,0.98999999999999999,0,0,1
detail.grid=32x24x16
detail.samples=3,8
detail.display=0.40000000000000002,0.01,1
detail.clamp_passes=8
detail.energy=10000;0,10,20,30,40,50,60,65,70,75,80,
detail.solve=0.0001,0.99999000000000005,0,1,2000,9.9999999999999995e-08,0
close_horizon=1
detail_only_if_better=1
compress_rgb=0
wavelengths=,0
isotropy=0
error=20000,160
preset=production
prediction=1,128,64,1,1,0;studio,key-rim,directional,
target=0;16x8x16,24x10x24,32x24x16,40x20x40,48x24x48,64x32x64,
)"},
    {"fine", true, R"(fit.grid=90,1,90,180
fit.g=90,1
fit.channels=rgb
fit.phi_d_samples=0
fit.volume_weight=0
fit.importance=2,2
fit.compressive=1,0.01
fit.acceleration=2
fit.g_pin=0.01
fit.smith_start=1,0
fit.iterations=200,1.0000000000000001e-05,0
compression=0.98999999999999999,0.98999999999999999,0,0,1
detail.grid=40x20x40
detail.samples=3,8
detail.display=0.40000000000000002,0.01,1
detail.clamp_passes=8
detail.energy=10000;0,10,20,30,40,50,60,65,70,75,80,
detail.solve=0.0001,0.99999000000000005,0,1,2000,9.9999999999999995e-08,0
close_horizon=1
detail_only_if_better=1
compress_rgb=0
wavelengths=,0
isotropy=0
error=20000,160
preset=fine
prediction=1,128,64,1,1,0;studio,key-rim,directional,
target=0;16x8x16,24x10x24,32x24x16,40x20x40,48x24x48,64x32x64,
)"},
    {"fine", false, R"(fit.grid=90,180,90,180
fit.g=90,180
fit.channels=rgb
fit.phi_d_samples=8
fit.volume_weight=0
fit.importance=2,2
fit.compressive=1,0.01
fit.acceleration=2
fit.g_pin=0.01
fit.smith_start=1,0
fit.iterations=200,1.0000000000000001e-05,0
compression=0.98999999999999999,0.98999999999999999,0,0,1
detail.grid=40x20x40
detail.samples=3,8
detail.display=0.40000000000000002,0.01,1
detail.clamp_passes=8
detail.energy=10000;0,10,20,30,40,50,60,65,70,75,80,
detail.solve=0.0001,0.99999000000000005,0,1,2000,9.9999999999999995e-08,0
close_horizon=1
detail_only_if_better=1
compress_rgb=0
wavelengths=,0
isotropy=0
error=20000,160
preset=fine
prediction=1,128,64,1,1,0;studio,key-rim,directional,
target=0;16x8x16,24x10x24,32x24x16,40x20x40,48x24x48,64x32x64,
)"},
    {"paper", true, R"(fit.grid=90,1,90,180
fit.g=90,1
fit.channels=rgb
fit.phi_d_samples=0
fit.volume_weight=0
fit.importance=2,2
fit.compressive=1,0.01
fit.acceleration=1
fit.g_pin=0
fit.smith_start=1,0
fit.iterations=500,9.9999999999999995e-07,0
compression=0.98999999999999999,0.98999999999999999,0,0,0
detail.grid=0x0x0
detail.samples=3,8
detail.display=0.40000000000000002,0.01,1
detail.clamp_passes=8
detail.energy=10000;0,10,20,30,40,50,60,65,70,75,80,
detail.solve=0.0001,0.99999000000000005,0,1,2000,9.9999999999999995e-08,0
close_horizon=0
detail_only_if_better=1
compress_rgb=0
wavelengths=,0
isotropy=0
error=20000,160
preset=paper
prediction=1,128,64,1,1,0;studio,
target=0;16x8x16,24x10x24,32x24x16,40x20x40,48x24x48,64x32x64,
)"},
    {"paper", false, R"(fit.grid=90,180,90,180
fit.g=90,180
fit.channels=rgb
fit.phi_d_samples=16
fit.volume_weight=0
fit.importance=2,2
fit.compressive=1,0.01
fit.acceleration=1
fit.g_pin=0
fit.smith_start=1,0
fit.iterations=500,9.9999999999999995e-07,0
compression=0.98999999999999999,0.98999999999999999,0,0,0
detail.grid=0x0x0
detail.samples=3,8
detail.display=0.40000000000000002,0.01,1
detail.clamp_passes=8
detail.energy=10000;0,10,20,30,40,50,60,65,70,75,80,
detail.solve=0.0001,0.99999000000000005,0,1,2000,9.9999999999999995e-08,0
close_horizon=0
detail_only_if_better=1
compress_rgb=0
wavelengths=,0
isotropy=0
error=20000,160
preset=paper
prediction=1,128,64,1,1,0;studio,
target=0;16x8x16,24x10x24,32x24x16,40x20x40,48x24x48,64x32x64,
)"},
};

TEST(PresetValues, EveryPresetResolvesAsBefore) {
    for (const Pinned& p : kBefore) {
        EXPECT_EQ(every_field(preset_settings(parse_convert_preset(p.preset, "preset"), p.isotropic)), p.fields)
            << p.preset << (p.isotropic ? " isotropic" : " anisotropic");
    }
}

}  // namespace
