// The fitter's settings (fit_npf's AwlsOptions, its bounds from awls_limits) and the SVD's
// compression (CompressionOptions): declared here, beside convert.cpp's fit and compression
// stages, in the converter because each row applies to ConvertSettings.
#include "setting_rows.h"

#include <npf/core/number_text.h>

namespace npf::settings_rows {

namespace {

// The two whole numbers of a pair setting (g_grid, rank), and their text.
void set_pair(int& first, int& second, const SettingValue& v) {
    first = int(v.numbers[0]);
    second = int(v.numbers[1]);
}
std::string pair_text(int first, int second) { return std::to_string(first) + "," + std::to_string(second); }

std::string g_prior_name(const AwlsOptions& o) {
    if (o.smith_start) return o.bound_g ? "smith" : "smith-start";
    return o.bound_g ? "bounded" : "free";
}

}  // namespace

Rows fit_grid_settings() {
    Rows rows;
    const Range grid_axis{awls_limits::kMinCells, awls_limits::kMaxCells}, phi_axis{awls_limits::kMinPhiCells, awls_limits::kMaxCells};
    Row r;
    r = always_hashed(whole("grid", {grid_axis, phi_axis, grid_axis, grid_axis}, "fitting grid THETA_H,PHI_H,THETA_D,PHI_D (D and F tables)"));
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.fit.grid = {int(v.numbers[0]), int(v.numbers[1]), int(v.numbers[2]), int(v.numbers[3])};
    };
    r.read = [](const ConvertSettings& s) {
        const RusinkiewiczGrid& g = s.fit.grid;
        return std::to_string(g.theta_h) + "," + std::to_string(g.phi_h) + "," + std::to_string(g.theta_d) + "," + std::to_string(g.phi_d);
    };
    r.metadata = [](const ConvertSettings& s) {
        const RusinkiewiczGrid& g = s.fit.grid;
        return Lines{{"fit_grid", std::to_string(g.theta_h) + "x" + std::to_string(g.phi_h) + "x" + std::to_string(g.theta_d) +
                                      "x" + std::to_string(g.phi_d)}};
    };
    rows.push_back(r);

    r = always_hashed(whole("g_grid", {grid_axis, phi_axis}, "G table THETA,PHI"));
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) { set_pair(s.fit.g_theta, s.fit.g_phi, v); };
    r.read = [](const ConvertSettings& s) { return pair_text(s.fit.g_theta, s.fit.g_phi); };
    rows.push_back(r);

    r = always_hashed(whole("phi_d_samples", {{0, awls_limits::kMaxPhiDSamples}}, "phi_d samples per ring (0: every grid cell)"));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.phi_d_samples = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.fit.phi_d_samples); };
    r.metadata = [](const ConvertSettings& s) {
        return Lines{{"fit_phi_d_samples", std::to_string(s.fit.phi_d_samples > 0 ? s.fit.phi_d_samples : s.fit.grid.phi_d)}};
    };
    rows.push_back(r);

    // Asking for compression compresses RGB too: resolve_convert_settings sets compress_rgb when
    // pca or rank is given (a preset's ratio does not).
    r = always_hashed(number("pca", 2, 2, {{0, 1, true}}, "ratios must lie in (0, 1]",
                      "cumulative contribution ratios D,G kept by the SVD (e.g. 0.99,0.95; 1 = lossless)"));
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.compression.d_ratio = v.numbers[0];
        s.compression.g_ratio = v.numbers[1];
    };
    r.read = [](const ConvertSettings& s) { return g17(s.compression.d_ratio) + "," + g17(s.compression.g_ratio); };
    rows.push_back(r);

    r = choice("pca_rule", {"per-channel", "total"},
               "per-channel: the --pca ratio holds for every channel's table, so a "
               "colour that shifts with angle keeps its component, or total (the paper's rule: for all channels together)");
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.compression.per_channel = v.text == "per-channel"; };
    r.read = [](const ConvertSettings& s) { return std::string(s.compression.per_channel ? "per-channel" : "total"); };
    r.metadata = [](const ConvertSettings& s) { return Lines{{"compression_rule", s.compression.per_channel ? "per-channel" : "total"}}; };
    rows.push_back(r);

    r = always_hashed(whole("rank", {{1, 100000}, {1, 100000}}, "fixed SVD ranks D,G (overrides --pca; unset: --pca decides)"));
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) { set_pair(s.compression.d_rank, s.compression.g_rank, v); };
    r.read = [](const ConvertSettings& s) { return pair_text(s.compression.d_rank, s.compression.g_rank); };
    rows.push_back(r);

    r = preset_only(always_hashed(switched("compress_rgb", "")));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.compress_rgb = v.on; };
    r.read = [](const ConvertSettings& s) { return std::string(s.compress_rgb ? "true" : "false"); };
    rows.push_back(r);
    return rows;
}

Rows fit_weight_settings() {
    Rows rows;
    Row r;
    r = always_hashed(number("importance", 1, 2, {}, "",
                      "w_I powers: P for (cos_i cos_o)^P, or PV,PL for cos_i^PV cos_o^PL (1,2 weighs errors as a render does; "
                      "docs/fitting.md)"));
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.fit.importance_power_view = v.numbers.front();
        s.fit.importance_power_light = v.numbers.back();
    };
    // The light power only when it differs, so that symmetric settings keep their old hashes.
    r.read = [](const ConvertSettings& s) {
        const AwlsOptions& o = s.fit;
        return g17(o.importance_power_view) +
               (o.importance_power_light != o.importance_power_view ? "," + g17(o.importance_power_light) : std::string());
    };
    r.metadata = [](const ConvertSettings& s) {
        const AwlsOptions& o = s.fit;
        return Lines{{"fit_importance_power", o.importance_power_view == o.importance_power_light
                                                  ? number_text(o.importance_power_view)
                                                  : number_text(o.importance_power_view) + "," + number_text(o.importance_power_light)}};
    };
    rows.push_back(r);

    r = always_hashed(number("compressive", 1, 1, {}, "", "w_C power q: (rho + eps)^-q"));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.compressive_power = v.numbers[0]; };
    r.read = [](const ConvertSettings& s) { return g17(s.fit.compressive_power); };
    r.metadata = [](const ConvertSettings& s) { return Lines{{"fit_compressive_power", number_text(s.fit.compressive_power)}}; };
    rows.push_back(r);

    r = always_hashed(number("epsilon", 1, 1, {{0, kAny, true}}, "must be positive", "w_C epsilon (1/sr)"));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.compressive_epsilon = v.numbers[0]; };
    r.read = [](const ConvertSettings& s) { return g17(s.fit.compressive_epsilon); };
    r.metadata = [](const ConvertSettings& s) { return Lines{{"fit_compressive_epsilon", number_text(s.fit.compressive_epsilon)}}; };
    rows.push_back(r);

    r = always_hashed(choice("volume_weight", {"paper", "three-angle"}, "paper or three-angle (Bagher et al.)"));
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.fit.volume_weight = v.text == "paper" ? VolumeWeight::Paper : VolumeWeight::ThreeAngle;
    };
    r.read = [](const ConvertSettings& s) { return std::string(s.fit.volume_weight == VolumeWeight::Paper ? "paper" : "three-angle"); };
    r.metadata = [](const ConvertSettings& s) {
        return Lines{{"fit_volume_weight", s.fit.volume_weight == VolumeWeight::Paper ? "paper" : "three-angle"}};
    };
    rows.push_back(r);

    r = always_hashed(whole("iterations", {{1, awls_limits::kMaxIterations}}, "most AWLS sweeps per block of channels"));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.max_iterations = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.fit.max_iterations); };
    r.metadata = [](const ConvertSettings& s) { return Lines{{"fit_max_iterations", std::to_string(s.fit.max_iterations)}}; };
    rows.push_back(r);

    r = always_hashed(number("tolerance", 1, 1, {{0, kAny}}, "must not be negative",
                      "stop when a sweep lowers the weighted error by less than this, relative"));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.tolerance = v.numbers[0]; };
    r.read = [](const ConvertSettings& s) { return g17(s.fit.tolerance); };
    r.metadata = [](const ConvertSettings& s) { return Lines{{"fit_tolerance", number_text(s.fit.tolerance)}}; };
    rows.push_back(r);

    r = always_hashed(choice("g_prior", {"smith", "smith-start", "bounded", "free"},
                      "smith (G starts from Smith's masking of D and stays <= 1), smith-start (starts there only), bounded (G <= "
                      "1 only) or free"));
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.fit.smith_start = v.text == "smith" || v.text == "smith-start";
        s.fit.bound_g = v.text == "smith" || v.text == "bounded";
    };
    r.read = [](const ConvertSettings& s) { return g_prior_name(s.fit); };
    rows.push_back(r);

    // What it sets is the acceleration row's (in the hash and the metadata).
    r = switched("plain", "no line-search extrapolation (the paper's plain alternation)");
    r.hash = SettingHash::Never;
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        if (v.on) s.fit.acceleration = AwlsOptions::Acceleration::None;
    };
    r.read = [](const ConvertSettings& s) {
        return std::string(s.fit.acceleration == AwlsOptions::Acceleration::None ? "true" : "false");
    };
    rows.push_back(r);

    // The fit's convergence options, which the presets set (the paper preset keeps its line search).
    r = preset_only(always_hashed(choice("acceleration", {"anderson", "line-search", "none"}, "")));
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.fit.acceleration = v.text == "anderson"      ? AwlsOptions::Acceleration::Anderson
                             : v.text == "line-search" ? AwlsOptions::Acceleration::LineSearch
                                                       : AwlsOptions::Acceleration::None;
    };
    r.read = [](const ConvertSettings& s) {
        const AwlsOptions::Acceleration a = s.fit.acceleration;
        return std::string(a == AwlsOptions::Acceleration::Anderson     ? "anderson"
                           : a == AwlsOptions::Acceleration::LineSearch ? "line-search"
                                                                        : "none");
    };
    r.metadata = [read = r.read](const ConvertSettings& s) { return Lines{{"fit_acceleration", read(s)}}; };
    rows.push_back(r);

    r = preset_only(always_hashed(number("g_pin", 1, 1, {{0, kAny}}, "must not be negative", "")));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.g_pin = v.numbers[0]; };
    r.read = [](const ConvertSettings& s) { return g17(s.fit.g_pin); };
    r.metadata = [](const ConvertSettings& s) { return Lines{{"fit_g_pin", number_text(s.fit.g_pin)}}; };
    rows.push_back(r);
    return rows;
}

}  // namespace npf::settings_rows
