// The detail layer's settings (fit_detail_layer's DetailOptions), and the horizon closed before
// it. Their metadata describe the layer written: none without one (the settings as fitted carry
// the written grid, convert.cpp).
#include "setting_rows.h"

#include <npf/core/number_text.h>

namespace npf::settings_rows {

namespace {

bool has_layer(const ConvertSettings& fitted) { return !fitted.detail.grid.empty(); }

// A detail setting's metadata: its one line where the file has a layer.
std::function<Lines(const ConvertSettings&)> layer_line(std::string key, std::function<std::string(const ConvertSettings&)> value) {
    return [key = std::move(key), value = std::move(value)](const ConvertSettings& s) { return has_layer(s) ? Lines{{key, value(s)}} : Lines{}; };
}

// A number among the detail fit's options: applied, read and recorded (where the file has a layer).
Row detail_number(Row r, double DetailOptions::*field, std::string metadata_key) {
    r.apply = [field](ConvertSettings& s, const SettingValue& v) { s.detail.*field = v.numbers[0]; };
    r.read = [field](const ConvertSettings& s) { return g17(s.detail.*field); };
    r.metadata = layer_line(std::move(metadata_key), [field](const ConvertSettings& s) { return number_text(s.detail.*field); });
    return r;
}

}  // namespace

Rows detail_settings() {
    Rows rows;
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
    r.metadata = [](const ConvertSettings& s) {
        return has_layer(s) ? Lines{{"detail_grid", grid_text(s.detail.grid, 'x')},
                                    {"detail_samples_per_cell", std::to_string(s.detail.samples_per_cell)}}
                            : Lines{};
    };
    rows.push_back(r);

    r = number("detail_energy", 1, 1, {{0, kAny}}, "must not be negative", "weight of the detail fit's energy term (0: none)");
    rows.push_back(detail_number(r, &DetailOptions::energy_weight, "detail_energy_weight"));

    r = choice("horizon", {"closed", "open"},
               "closed (G falls to 0 at the horizon, no light gained at silhouettes) or open (G "
               "as fitted; the paper preset)");
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.close_horizon = v.text == "closed"; };
    r.read = [](const ConvertSettings& s) { return std::string(s.close_horizon ? "closed" : "open"); };
    rows.push_back(r);

    r = number("detail_weight", 1, 1, {{0, detail_limits::kMaxDisplayPower}}, "",
               "power p of the detail fit's display weight (f + eps)^-p (0: plain least squares)");
    rows.push_back(detail_number(r, &DetailOptions::display_power, "detail_display_power"));

    r = choice("detail_measure", {"half-angle", "solid-angle"},
               "half-angle (every half-vector angle counts alike, so a narrow peak keeps its height) or "
               "solid-angle (Rusinkiewicz's cell measure: a peak narrower than a degree weighs almost nothing)");
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.detail.measure = v.text == "solid-angle" ? DetailOptions::Measure::SolidAngle : DetailOptions::Measure::HalfAngle;
    };
    r.read = [](const ConvertSettings& s) {
        return std::string(s.detail.measure == DetailOptions::Measure::SolidAngle ? "solid-angle" : "half-angle");
    };
    r.metadata = layer_line("detail_measure", r.read);
    rows.push_back(r);

    r = whole("detail_clamp_passes", {{0, detail_limits::kMaxClampPasses}},
              "refits of the detail layer's energy targets to the clamped model max(0, NPF + r) (0: none)");
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.detail.clamp_passes = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.detail.clamp_passes); };
    r.metadata = layer_line("detail_clamp_passes", r.read);
    rows.push_back(r);

    r = number("detail_views", 1, 0, {}, "", "view angles (degrees) at which the detail fit holds the source's albedo");
    r.takes_list = true;
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.detail.energy_views_deg = v.numbers; };
    r.read = [](const ConvertSettings& s) {
        std::vector<std::string> views;
        for (double d : s.detail.energy_views_deg) views.push_back(g17(d));
        return join(views, ",");
    };
    rows.push_back(r);
    return rows;
}

}  // namespace npf::settings_rows
