// The conversion settings' rows, in groups (convert_settings_table.cpp puts them together in the
// order of `npf convert --help`), and the row makers they share.
#include "convert_settings_rows.h"

#include <npf/core/channels.h>
#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/core/text.h>
#include <npf/render/lighting.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace npf::settings_rows {

// Numbers in hash text: every digit (content hash version 1).
std::string g17(double v) { return number_text(v, 17); }

std::vector<std::string> split(const std::string& v, char separator) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t at = v.find(separator, start);
        out.push_back(v.substr(start, at == std::string::npos ? std::string::npos : at - start));
        if (at == std::string::npos) return out;
        start = at + 1;
    }
}

std::string join(const std::vector<std::string>& parts, const char* separator) {
    std::string out;
    for (const std::string& p : parts) out += (out.empty() ? "" : separator) + p;
    return out;
}

std::string range_text(const Range& r) {
    return std::string(r.low_open ? "(" : "[") + g17(r.low) + ", " + g17(r.high) + "]";
}

namespace {

std::string grid_text(const DetailGrid& g, char separator) {
    const std::string sep(1, separator);
    return std::to_string(g.theta_h) + sep + std::to_string(g.theta_d) + sep + std::to_string(g.phi_d);
}

// Row makers: the common kinds in one line each.
Row row_of(std::string key, SettingKind kind, std::string help) {
    Row r;
    r.key = std::move(key);
    r.kind = kind;
    r.help = std::move(help);
    return r;
}

Row whole(std::string key, std::vector<Range> ranges, std::string help) {
    Row r = row_of(std::move(key), SettingKind::Whole, std::move(help));
    r.least_parts = r.most_parts = ranges.size();
    r.ranges = std::move(ranges);
    return r;
}

Row number(std::string key, std::size_t least_parts, std::size_t most_parts, std::vector<Range> ranges, std::string range_problem,
           std::string help) {
    Row r = row_of(std::move(key), SettingKind::Number, std::move(help));
    r.least_parts = least_parts;
    r.most_parts = most_parts;
    r.ranges = std::move(ranges);
    r.range_problem = std::move(range_problem);
    return r;
}

Row choice(std::string key, std::vector<std::string> choices, std::string help) {
    Row r = row_of(std::move(key), SettingKind::Choice, std::move(help));
    r.choices = std::move(choices);
    return r;
}

Row text(std::string key, std::function<void(const std::string&, const std::string&)> check, std::string help) {
    Row r = row_of(std::move(key), SettingKind::Text, std::move(help));
    r.check = std::move(check);
    return r;
}

Row switched(std::string key, std::string help) { return row_of(std::move(key), SettingKind::Switch, std::move(help)); }

// An Always row: its place in the version 1 hash text.
Row hashed(Row r, int order) {
    r.hash = SettingHash::Always;
    r.hash_order = order;
    return r;
}

std::string g_prior_name(const AwlsOptions& o) {
    if (o.smith_start) return o.bound_g ? "smith" : "smith-start";
    return o.bound_g ? "bounded" : "free";
}

}  // namespace

// What is fitted: the preset, the channels, the isotropy.
void add_source_rows(ConvertSettingsTable& t) {
    Row r;

    r = hashed(choice("preset", {"preview", "production", "fine", "paper"},
                      "preview, production, fine or paper (the paper's pure model; docs/fitting.md)"), 0);
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.preset = parse_convert_preset(v.text, "preset"); };
    r.read = [](const ConvertSettings& s) { return std::string(convert_preset_name(s.preset)); };
    r.metadata_order = 1;
    r.metadata = [](const ConvertSettings& s) { return Lines{{"preset", convert_preset_name(s.preset)}}; };
    t.push_back(r);

    r = hashed(text("wavelengths", [](const std::string& v, const std::string& what) { parse_channel_list(v, what); },
                    "channels to fit: rgb, start:end:count or a,b,c nm (unset: the source's own)"), 14);
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.wavelengths = v.text; };
    r.read = [](const ConvertSettings& s) { return s.wavelengths; };
    t.push_back(r);

    r = hashed(whole("max_wavelengths", {{0, 100000}}, "keep at most this many of the source's wavelengths, evenly spread (0: all)"), 15);
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.max_wavelengths = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.max_wavelengths); };
    t.push_back(r);

    // Also read before the preset: it decides the preset's grids (resolve_convert_settings).
    r = hashed(choice("isotropy", {"auto", "isotropic", "anisotropic"}, "auto (as the source), isotropic or anisotropic"), 16);
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.isotropy = v.text == "isotropic" ? Isotropy::Isotropic : v.text == "anisotropic" ? Isotropy::Anisotropic : Isotropy::Auto;
    };
    r.read = [](const ConvertSettings& s) {
        return std::string(s.isotropy == Isotropy::Isotropic ? "isotropic" : s.isotropy == Isotropy::Anisotropic ? "anisotropic" : "auto");
    };
    r.hash_lines = [](const ConvertSettings& s) { return "isotropy=" + std::to_string(int(s.isotropy)) + "\n"; };
    t.push_back(r);
}

// The fit's grids and the SVD's compression.
void add_grid_rows(ConvertSettingsTable& t) {
    const Range grid_axis{awls_limits::kMinCells, awls_limits::kMaxCells}, phi_axis{awls_limits::kMinPhiCells, awls_limits::kMaxCells};
    Row r;
    r = hashed(whole("grid", {grid_axis, phi_axis, grid_axis, grid_axis}, "fitting grid THETA_H,PHI_H,THETA_D,PHI_D (D and F tables)"), 1);
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.fit.grid = {int(v.numbers[0]), int(v.numbers[1]), int(v.numbers[2]), int(v.numbers[3])};
    };
    r.read = [](const ConvertSettings& s) {
        const RusinkiewiczGrid& g = s.fit.grid;
        return std::to_string(g.theta_h) + "," + std::to_string(g.phi_h) + "," + std::to_string(g.theta_d) + "," + std::to_string(g.phi_d);
    };
    r.metadata_order = 2;
    r.metadata = [](const ConvertSettings& s) {
        const RusinkiewiczGrid& g = s.fit.grid;
        return Lines{{"fit_grid", std::to_string(g.theta_h) + "x" + std::to_string(g.phi_h) + "x" + std::to_string(g.theta_d) +
                                      "x" + std::to_string(g.phi_d)}};
    };
    t.push_back(r);

    r = hashed(whole("g_grid", {grid_axis, phi_axis}, "G table THETA,PHI"), 2);
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.fit.g_theta = int(v.numbers[0]);
        s.fit.g_phi = int(v.numbers[1]);
    };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.fit.g_theta) + "," + std::to_string(s.fit.g_phi); };
    t.push_back(r);

    r = hashed(whole("phi_d_samples", {{0, awls_limits::kMaxPhiDSamples}}, "phi_d samples per ring (0: every grid cell)"), 3);
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.phi_d_samples = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.fit.phi_d_samples); };
    r.metadata_order = 3;  // the samples per ring the fit took
    r.metadata = [](const ConvertSettings& s) {
        return Lines{{"fit_phi_d_samples", std::to_string(s.fit.phi_d_samples > 0 ? s.fit.phi_d_samples : s.fit.grid.phi_d)}};
    };
    t.push_back(r);

    // Asking for compression compresses RGB too (ConvertSettings::compress_rgb).
    r = hashed(number("pca", 2, 2, {{0, 1, true}}, "ratios must lie in (0, 1]",
                      "cumulative contribution ratios D,G kept by the SVD (e.g. 0.99,0.95; 1 = lossless)"), 12);
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.compression.d_ratio = v.numbers[0];
        s.compression.g_ratio = v.numbers[1];
        s.compress_rgb = true;
    };
    r.read = [](const ConvertSettings& s) { return g17(s.compression.d_ratio) + "," + g17(s.compression.g_ratio); };
    t.push_back(r);

    r = choice("pca_rule", {"per-channel", "total"},
               "per-channel: the --pca ratio holds for every channel's table, so a "
               "colour that shifts with angle keeps its component, or total (the paper's rule: for all channels together)");
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.compression.per_channel = v.text == "per-channel"; };
    r.read = [](const ConvertSettings& s) { return std::string(s.compression.per_channel ? "per-channel" : "total"); };
    t.push_back(r);

    r = hashed(whole("rank", {{1, 100000}, {1, 100000}}, "fixed SVD ranks D,G (overrides --pca; unset: --pca decides)"), 13);
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.compression.d_rank = int(v.numbers[0]);
        s.compression.g_rank = int(v.numbers[1]);
        s.compress_rgb = true;
    };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.compression.d_rank) + "," + std::to_string(s.compression.g_rank); };
    r.hash_lines = [](const ConvertSettings& s) {
        return "rank=" + std::to_string(s.compression.d_rank) + "," + std::to_string(s.compression.g_rank) +
               "\ncompress_rgb=" + std::to_string(s.compress_rgb) + "\n";
    };
    t.push_back(r);
}

// The fit's weights and its iterations.
void add_weight_rows(ConvertSettingsTable& t) {
    Row r;
    r = hashed(number("importance", 1, 2, {}, "",
                      "w_I powers: P for (cos_i cos_o)^P, or PV,PL for cos_i^PV cos_o^PL (1,2 weighs errors as a render does; "
                      "docs/fitting.md)"), 5);
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
    r.metadata_order = 5;  // one value when symmetric (as before the split), else "view,light"
    r.metadata = [](const ConvertSettings& s) {
        const AwlsOptions& o = s.fit;
        return Lines{{"fit_importance_power", o.importance_power_view == o.importance_power_light
                                                  ? number_text(o.importance_power_view)
                                                  : number_text(o.importance_power_view) + "," + number_text(o.importance_power_light)}};
    };
    t.push_back(r);

    r = hashed(number("compressive", 1, 1, {}, "", "w_C power q: (rho + eps)^-q"), 6);
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.compressive_power = v.numbers[0]; };
    r.read = [](const ConvertSettings& s) { return g17(s.fit.compressive_power); };
    r.metadata_order = 6;
    r.metadata = [](const ConvertSettings& s) { return Lines{{"fit_compressive_power", number_text(s.fit.compressive_power)}}; };
    t.push_back(r);

    r = hashed(number("epsilon", 1, 1, {{0, kAny, true}}, "must be positive", "w_C epsilon (1/sr)"), 7);
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.compressive_epsilon = v.numbers[0]; };
    r.read = [](const ConvertSettings& s) { return g17(s.fit.compressive_epsilon); };
    r.metadata_order = 7;
    r.metadata = [](const ConvertSettings& s) { return Lines{{"fit_compressive_epsilon", number_text(s.fit.compressive_epsilon)}}; };
    t.push_back(r);

    r = hashed(choice("volume_weight", {"paper", "three-angle"}, "paper or three-angle (Bagher et al.)"), 4);
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.fit.volume_weight = v.text == "paper" ? VolumeWeight::Paper : VolumeWeight::ThreeAngle;
    };
    r.read = [](const ConvertSettings& s) { return std::string(s.fit.volume_weight == VolumeWeight::Paper ? "paper" : "three-angle"); };
    r.metadata_order = 4;
    r.metadata = [](const ConvertSettings& s) {
        return Lines{{"fit_volume_weight", s.fit.volume_weight == VolumeWeight::Paper ? "paper" : "three-angle"}};
    };
    t.push_back(r);

    r = hashed(whole("iterations", {{1, awls_limits::kMaxIterations}}, "most AWLS sweeps per block of channels"), 10);
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.max_iterations = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.fit.max_iterations); };
    r.metadata_order = 8;
    r.metadata = [](const ConvertSettings& s) { return Lines{{"fit_max_iterations", std::to_string(s.fit.max_iterations)}}; };
    t.push_back(r);

    r = hashed(number("tolerance", 1, 1, {{0, kAny}}, "must not be negative",
                      "stop when a sweep lowers the weighted error by less than this, relative"), 11);
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.tolerance = v.numbers[0]; };
    r.read = [](const ConvertSettings& s) { return g17(s.fit.tolerance); };
    r.metadata_order = 9;
    r.metadata = [](const ConvertSettings& s) { return Lines{{"fit_tolerance", number_text(s.fit.tolerance)}}; };
    t.push_back(r);

    r = hashed(choice("g_prior", {"smith", "smith-start", "bounded", "free"},
                      "smith (G starts from Smith's masking of D and stays <= 1), smith-start (starts there only), bounded (G <= "
                      "1 only) or free"), 9);
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.fit.smith_start = v.text == "smith" || v.text == "smith-start";
        s.fit.bound_g = v.text == "smith" || v.text == "bounded";
    };
    r.read = [](const ConvertSettings& s) { return g_prior_name(s.fit); };
    r.hash_lines = [](const ConvertSettings& s) {
        return "smith_start=" + std::to_string(s.fit.smith_start) + "\nbound_g=" + std::to_string(s.fit.bound_g) + "\n";
    };
    t.push_back(r);

    // Its hash lines carry the G pin too: the fit's convergence options, which the presets set.
    r = hashed(switched("plain", "no line-search extrapolation (the paper's plain alternation)"), 8);
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        if (v.on) s.fit.acceleration = AwlsOptions::Acceleration::None;
    };
    r.read = [](const ConvertSettings& s) {
        return std::string(s.fit.acceleration == AwlsOptions::Acceleration::None ? "true" : "false");
    };
    r.hash_lines = [](const ConvertSettings& s) {
        return "acceleration=" + std::to_string(int(s.fit.acceleration)) + "\ng_pin=" + g17(s.fit.g_pin) + "\n";
    };
    r.metadata_order = 10;
    r.metadata = [](const ConvertSettings& s) {
        const AwlsOptions::Acceleration a = s.fit.acceleration;
        return Lines{{"fit_acceleration", a == AwlsOptions::Acceleration::Anderson     ? "anderson"
                                          : a == AwlsOptions::Acceleration::LineSearch ? "line-search"
                                                                                       : "none"},
                     {"fit_g_pin", number_text(s.fit.g_pin)}};
    };
    t.push_back(r);
}

// The detail layer.
void add_detail_rows(ConvertSettingsTable& t) {
    Row r;
    r = text("detail",
             [](const std::string& v, const std::string& what) {
                 if (v != "none") parse_detail_grid(v, ',', what);
             },
             "detail layer grid THETA_H,THETA_D,PHI_D (u_h, theta_d, phi_d), or none (the paper's pure model; docs/fitting.md)");
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.detail.grid = v.text == "none" ? DetailGrid{} : parse_detail_grid(v.text, ',', "detail");
    };
    r.read = [](const ConvertSettings& s) { return s.detail.grid.empty() ? std::string("none") : grid_text(s.detail.grid, ','); };
    t.push_back(r);

    r = number("detail_energy", 1, 1, {{0, kAny}}, "must not be negative", "weight of the detail fit's energy term (0: none)");
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.detail.energy_weight = v.numbers[0]; };
    r.read = [](const ConvertSettings& s) { return g17(s.detail.energy_weight); };
    t.push_back(r);

    r = choice("horizon", {"closed", "open"},
               "closed (G falls to 0 at the horizon, no light gained at silhouettes) or open (G "
               "as fitted; the paper preset)");
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.close_horizon = v.text == "closed"; };
    r.read = [](const ConvertSettings& s) { return std::string(s.close_horizon ? "closed" : "open"); };
    t.push_back(r);

    r = number("detail_weight", 1, 1, {{0, 4}}, "must lie in [0, 4]",
               "power p of the detail fit's display weight (f + eps)^-p (0: plain least squares)");
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.detail.display_power = v.numbers[0]; };
    r.read = [](const ConvertSettings& s) { return g17(s.detail.display_power); };
    t.push_back(r);

    r = choice("detail_measure", {"half-angle", "solid-angle"},
               "half-angle (every half-vector angle counts alike, so a narrow peak keeps its height) or "
               "solid-angle (Rusinkiewicz's cell measure: a peak narrower than a degree weighs almost nothing)");
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.detail.measure = v.text == "solid-angle" ? DetailOptions::Measure::SolidAngle : DetailOptions::Measure::HalfAngle;
    };
    r.read = [](const ConvertSettings& s) {
        return std::string(s.detail.measure == DetailOptions::Measure::SolidAngle ? "solid-angle" : "half-angle");
    };
    t.push_back(r);

    r = whole("detail_clamp_passes", {{0, 16}},
              "refits of the detail layer's energy targets to the clamped model max(0, NPF + r) (0: none)");
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.detail.clamp_passes = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.detail.clamp_passes); };
    t.push_back(r);

    r = number("detail_views", 1, 0, {}, "", "view angles (degrees) at which the detail fit holds the source's albedo");
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.detail.energy_views_deg = v.numbers; };
    r.read = [](const ConvertSettings& s) {
        std::vector<std::string> views;
        for (double d : s.detail.energy_views_deg) views.push_back(g17(d));
        return join(views, ",");
    };
    t.push_back(r);
}

// The measurements of the result and the prediction; threads.
void add_output_rows(ConvertSettingsTable& t) {
    Row r;
    r = hashed(whole("error_pairs", {{0, 100000000}}, "direction pairs of the BRDF-space error (0 skips it)"), 17);
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.error_pairs = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.error_pairs); };
    r.metadata_order = 11;  // only when measured (its results follow it)
    r.metadata = [](const ConvertSettings& s) {
        return s.error_pairs > 0 ? Lines{{"error_pairs", std::to_string(s.error_pairs)}} : Lines{};
    };
    t.push_back(r);

    // Not in the hash: content hash version 1 left it out, and adding it would redo every
    // output made with it. (A changed target does not redo a batch output.)
    r = text("target_psnr", [](const std::string& v, const std::string& what) { parse_target_psnr(v, what); },
             "predicted render PSNR to reach (dB): writes the smallest detail layer (none, 16x8x16 .. 64x32x64) that reaches it, "
             "or the best with a warning");
    r.hash = SettingHash::Never;
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.target_psnr = parse_target_psnr(v.text, "target_psnr"); };
    r.read = [](const ConvertSettings& s) { return g17(s.target_psnr); };
    t.push_back(r);

    r = text("target_grids", [](const std::string& v, const std::string& what) { parse_detail_ladder(v, what); },
             "with --target-psnr: the detail grids to try after none, growing");
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.target_ladder = parse_detail_ladder(v.text, "target_grids"); };
    r.read = [](const ConvertSettings& s) {
        std::vector<std::string> grids;
        for (const DetailGrid& g : s.target_ladder) grids.push_back(grid_text(g, 'x'));
        return join(grids, ",");
    };
    t.push_back(r);

    r = switched("no_predict", "skip the predicted render PSNR (per lighting, the source and the conversion at two seeds, 128x128 at 64 spp, key-rim "
                         "at 128, directional once without Monte Carlo; 64x64 at half the samples with the preview preset: a few seconds)");
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        if (v.on) s.predict_psnr = false;
    };
    r.read = [](const ConvertSettings& s) { return std::string(s.predict_psnr ? "false" : "true"); };
    t.push_back(r);

    // In the hash only when it differs from the preset's set: earlier outputs stay up to date.
    r = text("light", [](const std::string& v, const std::string& what) { render::parse_lighting_list(v, what); },
             "lightings the predicted PSNR judges (and --target-psnr meets), comma-separated: studio, key-rim, directional "
             "or a lat-long map file (the worst counts)");
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.prediction.lightings = render::parse_lighting_list(v.text, "light"); };
    r.read = [](const ConvertSettings& s) { return join(s.prediction.lightings, ","); };
    t.push_back(r);
    r = whole("threads", {{1, 1024}}, "threads (unset: all cores)");
    r.hash = SettingHash::Never;
    r.changes_output = false;
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.fit.threads = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.fit.threads); };
    t.push_back(r);
}

}  // namespace npf::settings_rows
