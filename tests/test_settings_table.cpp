// The conversion settings table (issue 18): one row is all a new setting needs, the CLI flags and
// the batch keys accept and reject the same values, and the batch content hash text is that of
// content hash version 1 byte for byte.
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/batch/config.h>
#include <npf/converter/convert_settings_table.h>
#include <npf/core/number_text.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace {

using namespace npf;
namespace batch = npf::batch;
using npf::testing::contains;

// runner.cpp's resolved_text before the table (content hash version 1), kept as the reference.
std::string g17(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}
std::string legacy_hash_text(const ConvertSettings& s) {
    const AwlsOptions& o = s.fit;
    std::string t;
    t += "preset=" + std::string(convert_preset_name(s.preset)) + "\n";
    t += "grid=" + std::to_string(o.grid.theta_h) + "," + std::to_string(o.grid.phi_h) + "," + std::to_string(o.grid.theta_d) +
         "," + std::to_string(o.grid.phi_d) + "\n";
    t += "g_grid=" + std::to_string(o.g_theta) + "," + std::to_string(o.g_phi) + "\n";
    t += "phi_d_samples=" + std::to_string(o.phi_d_samples) + "\n";
    t += "volume_weight=" + std::string(o.volume_weight == VolumeWeight::Paper ? "paper" : "three-angle") + "\n";
    t += "importance=" + g17(o.importance_power_view) +
         (o.importance_power_light != o.importance_power_view ? "," + g17(o.importance_power_light) : std::string()) +
         "\ncompressive=" + g17(o.compressive_power) +
         "\nepsilon=" + g17(o.compressive_epsilon) + "\n";
    t += "acceleration=" + std::to_string(int(o.acceleration)) + "\ng_pin=" + g17(o.g_pin) + "\nsmith_start=" + std::to_string(o.smith_start) +
         "\nbound_g=" + std::to_string(o.bound_g) + "\n";
    t += "iterations=" + std::to_string(o.max_iterations) + "\ntolerance=" + g17(o.tolerance) + "\n";
    t += "pca=" + g17(s.compression.d_ratio) + "," + g17(s.compression.g_ratio) + "\nrank=" +
         std::to_string(s.compression.d_rank) + "," + std::to_string(s.compression.g_rank) + "\n";
    t += "compress_rgb=" + std::to_string(s.compress_rgb) + "\nwavelengths=" + s.wavelengths +
         "\nmax_wavelengths=" + std::to_string(s.max_wavelengths) + "\n";
    t += "isotropy=" + std::to_string(int(s.isotropy)) + "\nerror_pairs=" + std::to_string(s.error_pairs) + "\n";
    return t;
}

// resolved_text(preset_settings(Production, isotropic)), captured before the table existed.
const char* const kProductionIsotropicHashText =
    "preset=production\ngrid=90,1,90,180\ng_grid=90,1\nphi_d_samples=0\nvolume_weight=paper\nimportance=2\ncompressive=1\n"
    "epsilon=0.01\nacceleration=2\ng_pin=0.01\nsmith_start=1\nbound_g=0\niterations=200\ntolerance=1.0000000000000001e-05\n"
    "pca=0.98999999999999999,0.98999999999999999\nrank=0,0\ncompress_rgb=0\nwavelengths=\nmax_wavelengths=0\nisotropy=0\n"
    "error_pairs=20000\n";

batch::Settings batch_settings(const std::string& defaults) {
    const std::string dir = npf::testing::temporary_folder("settings-table");
    return batch::parse_batch_config("output_dir: out\ninputs: m.bsdf\ndefaults: " + defaults + "\n", "t.yaml", dir).materials.at(0).settings;
}

TEST(SettingsTable, HashTextIsContentHashVersionOne) {
    EXPECT_EQ(convert_settings_hash_text(preset_settings(ConvertPreset::Production, true), true), kProductionIsotropicHashText);
    for (ConvertPreset p : {ConvertPreset::Preview, ConvertPreset::Production, ConvertPreset::Fine, ConvertPreset::Paper}) {
        for (bool iso : {true, false}) {
            EXPECT_EQ(convert_settings_hash_text(preset_settings(p, iso), iso), legacy_hash_text(preset_settings(p, iso)));
        }
    }
    // Every setting the batch knew before the table, through the batch's own mapping.
    for (const char* d : {"{preset: preview, grid: [20, 1, 18, 36], g_grid: [18, 1], pca: [0.9, 0.8], rank: [3, 2], importance: [1, 2], "
                          "compressive: 0.5, epsilon: 0.02, volume_weight: three-angle, iterations: 7, tolerance: 0.01, g_prior: bounded, "
                          "plain: true, error_pairs: 0, threads: 3, wavelengths: '400:700:4', max_wavelengths: 8, isotropy: anisotropic, "
                          "phi_d_samples: 4}",
                          "{importance: 1, g_prior: free, target_psnr: 40}", "{g_prior: smith-start, isotropy: isotropic, pca: [1, 1]}",
                          "{preset: paper, tolerance: 1e-7, epsilon: 1e-3, compressive: 0, plain: false}"}) {
        const batch::Settings s = batch_settings(d);
        for (bool source_isotropic : {true, false}) {
            const ConvertSettings c = batch::resolve_convert_settings(s, source_isotropic);
            const bool iso = c.isotropy == Isotropy::Auto ? source_isotropic : c.isotropy == Isotropy::Isotropic;
            EXPECT_EQ(convert_settings_hash_text(c, iso), legacy_hash_text(c)) << d;
        }
    }
}

// A setting the table does not have yet: the detail fit's samples per cell.
ConvertSettingsTable table_with_a_new_row() {
    ConvertSettingsTable table = convert_settings_table();
    ConvertSettingRow row;
    row.key = "detail_samples";
    row.kind = SettingKind::Whole;
    row.ranges = {{1, 16}};
    row.help = "samples per detail cell and axis";
    row.apply = [](ConvertSettings& s, const SettingValue& v) { s.detail.samples_per_cell = int(v.numbers[0]); };
    row.read = [](const ConvertSettings& s) { return std::to_string(s.detail.samples_per_cell); };
    row.metadata_order = 10;  // after the fit's settings
    row.metadata = [](const ConvertSettings& s) {
        return std::vector<std::pair<std::string, std::string>>{{"fit_detail_samples", std::to_string(s.detail.samples_per_cell)}};
    };
    table.push_back(row);
    return table;
}

TEST(SettingsTable, ANewSettingIsOneRow) {
    const ConvertSettingsTable table = table_with_a_new_row();
    const ConvertSettingRow& row = table.back();
    EXPECT_EQ(setting_flag(row), "--detail-samples");
    EXPECT_EQ(setting_default(row, ConvertPreset::Production, true), "3");
    EXPECT_THROW(check_setting(row, "0", "--detail-samples"), Error);
    EXPECT_THROW(check_setting(row, "x", "--detail-samples"), Error);

    const auto resolve = [&](const std::map<std::string, std::string>& given) {
        return resolve_convert_settings(
            table,
            [&](const ConvertSettingRow& r) -> std::optional<SettingValue> {
                const auto it = given.find(r.key);
                if (it == given.end()) return std::nullopt;
                return check_setting(r, it->second, setting_flag(r));
            },
            [](const ConvertSettingRow& r) { return setting_flag(r); }, true);
    };
    const ConvertSettings changed = resolve({{"detail_samples", "5"}, {"preset", "fine"}});
    EXPECT_EQ(changed.detail.samples_per_cell, 5);
    EXPECT_EQ(changed.preset, ConvertPreset::Fine);
    // In the hash text only where it differs from the preset's value: earlier hashes stay.
    const ConvertSettings unchanged = resolve({{"detail_samples", "3"}});
    EXPECT_EQ(convert_settings_hash_text(unchanged, true, table), kProductionIsotropicHashText);
    EXPECT_EQ(convert_settings_hash_text(changed, true, table),
              convert_settings_hash_text(changed, true) + "detail_samples=5\n");
    // And in the factor texture's metadata, after the fit's settings.
    auto lines = convert_settings_metadata(changed, 1, 11);
    lines.insert(lines.begin() + 11, {"fit_detail_samples", "5"});  // after fit_g_pin, before error_pairs
    EXPECT_EQ(convert_settings_metadata(changed, 1, 11, table), lines);
}

// convert.cpp's metadata lines of the settings before the table, kept as the reference.
std::string six(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}
std::vector<std::pair<std::string, std::string>> legacy_metadata(const ConvertSettings& s) {
    const AwlsOptions& o = s.fit;
    const RusinkiewiczGrid& g = o.grid;
    std::vector<std::pair<std::string, std::string>> m;
    m.emplace_back("preset", convert_preset_name(s.preset));
    m.emplace_back("fit_grid", std::to_string(g.theta_h) + "x" + std::to_string(g.phi_h) + "x" + std::to_string(g.theta_d) + "x" +
                                   std::to_string(g.phi_d));
    m.emplace_back("fit_phi_d_samples", std::to_string(o.phi_d_samples > 0 ? o.phi_d_samples : g.phi_d));
    m.emplace_back("fit_volume_weight", o.volume_weight == VolumeWeight::Paper ? "paper" : "three-angle");
    m.emplace_back("fit_importance_power", o.importance_power_view == o.importance_power_light
                                               ? six(o.importance_power_view)
                                               : six(o.importance_power_view) + "," + six(o.importance_power_light));
    m.emplace_back("fit_compressive_power", six(o.compressive_power));
    m.emplace_back("fit_compressive_epsilon", six(o.compressive_epsilon));
    m.emplace_back("fit_max_iterations", std::to_string(o.max_iterations));
    m.emplace_back("fit_tolerance", six(o.tolerance));
    m.emplace_back("fit_acceleration", o.acceleration == AwlsOptions::Acceleration::Anderson     ? "anderson"
                                        : o.acceleration == AwlsOptions::Acceleration::LineSearch ? "line-search"
                                                                                                   : "none");
    m.emplace_back("fit_g_pin", six(o.g_pin));
    if (s.error_pairs > 0) m.emplace_back("error_pairs", std::to_string(s.error_pairs));
    return m;
}

TEST(SettingsTable, MetadataLinesAreThoseBeforeTheTable) {
    for (ConvertPreset preset : {ConvertPreset::Preview, ConvertPreset::Production, ConvertPreset::Fine, ConvertPreset::Paper}) {
        for (bool isotropic : {true, false}) {
            ConvertSettings s = preset_settings(preset, isotropic);
            EXPECT_EQ(convert_settings_metadata(s, 1, 11), legacy_metadata(s)) << convert_preset_name(preset);
            s.fit.importance_power_light = 2.5;
            s.fit.acceleration = AwlsOptions::Acceleration::Anderson;
            s.fit.phi_d_samples = 0;
            s.error_pairs = 0;
            EXPECT_EQ(convert_settings_metadata(s, 1, 11), legacy_metadata(s)) << convert_preset_name(preset);
        }
    }
}

struct Candidate {
    std::string value;
    bool valid;
};

std::string number_text(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

// Values at and beyond each row's limits, generated from the table; Text rows by example.
std::vector<Candidate> candidates(const ConvertSettingRow& row) {
    static const std::map<std::string, std::vector<Candidate>> text_examples = {
        {"wavelengths", {{"rgb", true}, {"400:700:4", true}, {"450,550,650", true}, {"700:400:x", false}, {"blue", false}}},
        {"detail", {{"none", true}, {"32,12,32", true}, {"32,0,32", false}, {"32,12", false}}},
        {"target_psnr", {{"40", true}, {"0", false}, {"x", false}}},
        {"target_grids", {{"16x8x16,32x12x32", true}, {"32x12x32,16x8x16", false}, {"16x8", false}}},
        {"light", {{"studio", true}, {"key-rim,directional", true}, {"spotlight", false}, {"studio,studio", false}}},
    };
    std::vector<Candidate> out;
    switch (row.kind) {
    case SettingKind::Choice:
        for (const std::string& c : row.choices) out.push_back({c, true});
        out.push_back({"bogus", false});
        break;
    case SettingKind::Switch:
        break;  // a flag without a value: nothing to compare
    case SettingKind::Text: {
        const auto it = text_examples.find(row.key);
        if (it == text_examples.end()) ADD_FAILURE() << "no examples for the Text row " << row.key;
        else out = it->second;
        break;
    }
    case SettingKind::Whole:
    case SettingKind::Number: {
        const std::size_t n = std::max<std::size_t>(1, row.least_parts);
        const bool whole = row.kind == SettingKind::Whole;
        const auto range = [&](std::size_t i) {
            return row.ranges.empty() ? ConvertSettingRow::Range{0, 1} : row.ranges[std::min(i, row.ranges.size() - 1)];
        };
        // Every part at its low end (just inside an open one), then one part changed.
        std::vector<std::string> base;
        for (std::size_t i = 0; i < n; ++i) base.push_back(number_text(range(i).low_open ? range(i).low + 0.5 : range(i).low));
        const auto with = [&](std::size_t at, const std::string& part) {
            std::string v;
            for (std::size_t i = 0; i < n; ++i) v += (i ? "," : "") + (i == at ? part : base[i]);
            return v;
        };
        out.push_back({with(0, base[0]), true});
        for (std::size_t i = 0; i < n && !row.ranges.empty(); ++i) {
            const ConvertSettingRow::Range r = range(i);
            const double step = whole ? 1.0 : 0.25;
            if (std::isfinite(r.high)) {
                out.push_back({with(i, number_text(r.high)), true});
                out.push_back({with(i, number_text(r.high + step)), false});
            }
            out.push_back({with(i, number_text(r.low_open ? r.low : r.low - step)), false});
        }
        out.push_back({with(n - 1, "x"), false});
        out.push_back({with(n - 1, ""), false});
        if (whole) out.push_back({with(0, "1.5"), false});
        // One parser for every number (core/number_text.h): a blank is not part of one, for
        // --iterations as for --spp. (A batch list's items are trimmed, as YAML's "[16, 1, 16, 32]"
        // items are: blanks around its commas belong to the list.)
        if (!row.takes_list) out.push_back({with(0, " " + base[0]), false});
        if (row.most_parts > 0) {
            std::string too_many = with(0, base[0]);
            for (std::size_t k = n; k <= row.most_parts; ++k) too_many += ",1";
            out.push_back({too_many, false});
        }
        break;
    }
    }
    return out;
}

TEST(SettingsTable, CliFlagsAndBatchKeysAcceptTheSameValues) {
    const std::string dir = npf::testing::temporary_folder("settings-table-cli");
    for (const ConvertSettingRow& row : convert_settings_table()) {
        const std::string flag = setting_flag(row);
        for (const Candidate& c : candidates(row)) {
            bool batch_accepts = true;
            try {
                batch_settings("{" + row.key + ": '" + c.value + "'}");
            } catch (const Error& e) {
                batch_accepts = false;
                EXPECT_TRUE(contains(e.what(), "key 'defaults." + row.key + "'")) << e.what();
            }
            // A missing input: accepted values fail there, after every flag is checked.
            const npf::testing::ToolRun r =
                npf::testing::run_tool({"convert", dir + "/missing.bsdf", "-o", dir + "/x.exr", flag, c.value, "--quiet"});
            const bool cli_accepts = !contains(r.err, "error: " + flag + ":");
            EXPECT_NE(r.status, 0) << npf::testing::describe(r);
            EXPECT_EQ(cli_accepts, c.valid) << flag << " '" << c.value << "'\n" << npf::testing::describe(r);
            EXPECT_EQ(batch_accepts, c.valid) << row.key << ": '" << c.value << "'";
        }
        if (row.kind == SettingKind::Switch) {
            EXPECT_NO_THROW(batch_settings("{" + row.key + ": true}"));
            EXPECT_NO_THROW(batch_settings("{" + row.key + ": false}"));
            EXPECT_THROW(batch_settings("{" + row.key + ": maybe}"), Error);
        }
    }
}

// `npf convert --help` states the defaults the code uses: read from the presets, not written by
// hand (a help line once said --detail-weight defaulted to 1.17 while the code used 0.4).
TEST(SettingsTable, HelpStatesTheDefaultsTheCodeUses) {
    const npf::ConvertSettings production = npf::preset_settings(npf::ConvertPreset::Production, true);
    const ConvertSettingRow* weight = npf::find_setting(convert_settings_table(), "detail_weight");
    ASSERT_TRUE(weight);
    EXPECT_TRUE(contains(npf::setting_help(*weight), "(default: " + npf::exact_number_text(production.detail.display_power) + ")"))
        << npf::setting_help(*weight);
    for (const ConvertSettingRow& row : convert_settings_table()) {
        if (!row.read || row.kind == SettingKind::Switch) continue;
        const std::string value = npf::setting_default(row, npf::ConvertPreset::Production, true);
        const std::string help = npf::setting_help(row);
        const std::size_t at = help.find("(default: ");
        bool valid = !value.empty();
        try {
            if (valid) npf::check_setting(row, value, row.key);
        } catch (const Error&) {
            valid = false;
        }
        if (!valid) {
            EXPECT_EQ(at, std::string::npos) << row.key << ": an unset default is not stated: " << help;
            continue;
        }
        ASSERT_NE(at, std::string::npos) << row.key << ": " << help;
        std::string shown = help.substr(at + 10);
        shown = shown.substr(0, shown.find_first_of(";)"));
        const auto numbers = npf::parse_number_list(value);
        if (numbers) EXPECT_EQ(npf::parse_number_list(shown), numbers) << row.key << ": " << help;
        else EXPECT_EQ(shown, value) << row.key << ": " << help;
        // Nothing hand-written beside it.
        EXPECT_EQ(help.find("default"), at + 1) << row.key << ": " << help;
    }
}

// Every batch key of a conversion setting is a row, and every row a batch key.
TEST(SettingsTable, BatchKeysAreTheRows) {
    for (const ConvertSettingRow& row : convert_settings_table()) {
        const auto& names = batch::setting_names();
        EXPECT_NE(std::find(names.begin(), names.end(), row.key), names.end()) << row.key;
    }
}

}  // namespace
