// The settings of what a conversion measures and predicts (convert.cpp's error stages and
// psnr_prediction.h), and its threads.
#include "setting_rows.h"

#include <npf/render/lighting.h>

namespace npf::settings_rows {

Rows output_settings() {
    Rows rows;
    Row r;
    r = always_hashed(whole("error_pairs", {{0, 100000000}}, "direction pairs of the BRDF-space error (0 skips it)"));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.error_pairs = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.error_pairs); };
    r.metadata = [](const ConvertSettings& s) {
        return s.error_pairs > 0 ? Lines{{"error_pairs", std::to_string(s.error_pairs)}} : Lines{};
    };
    rows.push_back(r);

    // Not in the hash: content hash version 1 left it out, and adding it would redo every
    // output made with it. (A changed target does not redo a batch output.)
    r = text("target_psnr", [](const std::string& v, const std::string& what) { parse_target_psnr(v, what); },
             "predicted render PSNR to reach (dB): writes the smallest detail layer (none, 16x8x16 .. 64x32x64) that reaches it, "
             "or the best with a warning");
    r.hash = SettingHash::Never;
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.target_psnr = parse_target_psnr(v.text, "target_psnr"); };
    r.read = [](const ConvertSettings& s) { return g17(s.target_psnr); };
    rows.push_back(r);

    r = text("target_grids", [](const std::string& v, const std::string& what) { parse_detail_ladder(v, what); },
             "with --target-psnr: the detail grids to try after none, growing");
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.target_ladder = parse_detail_ladder(v.text, "target_grids"); };
    r.read = [](const ConvertSettings& s) {
        std::vector<std::string> grids;
        for (const DetailGrid& g : s.target_ladder) grids.push_back(grid_text(g, 'x'));
        return join(grids, ",");
    };
    rows.push_back(r);

    r = switched("no_predict", "skip the predicted render PSNR (per lighting, the source and the conversion at two seeds, 128x128 at 64 spp, key-rim "
                         "at 128, directional once without Monte Carlo; 64x64 at half the samples with the preview preset: a few seconds)");
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        if (v.on) s.predict_psnr = false;
    };
    r.read = [](const ConvertSettings& s) { return std::string(s.predict_psnr ? "false" : "true"); };
    rows.push_back(r);

    // In the hash only when it differs from the preset's set: earlier outputs stay up to date.
    r = text("light", [](const std::string& v, const std::string& what) { render::parse_lighting_list(v, what); },
             "lightings the predicted PSNR judges (and --target-psnr meets), comma-separated: studio, key-rim, directional "
             "or a lat-long map file (the worst counts)");
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.prediction.lightings = render::parse_lighting_list(v.text, "light"); };
    r.read = [](const ConvertSettings& s) { return join(s.prediction.lightings, ","); };
    rows.push_back(r);
    r = whole("threads", {{1, 1024}}, "threads (unset: all cores)");
    r.hash = SettingHash::Never;
    r.changes_output = false;
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.threads = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.fit.threads); };
    rows.push_back(r);
    // The preview preset's quicker measurements (an eighth of the prediction's renders, a third
    // of the energy error's samples; convert.h).
    r = preset_only(whole("prediction_size", {{16, 4096}}, ""));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.prediction.size = std::size_t(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.prediction.size); };
    rows.push_back(r);
    r = preset_only(whole("prediction_spp", {{1, 1 << 20}}, ""));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.prediction.spp = std::uint32_t(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.prediction.spp); };
    rows.push_back(r);
    r = preset_only(whole("energy_error_samples", {{1, 4096}}, ""));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.energy_error_samples = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.energy_error_samples); };
    rows.push_back(r);
    return rows;
}

}  // namespace npf::settings_rows
