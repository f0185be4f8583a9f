// The conversion settings table (issues 18, 36): the CLI flags and the batch keys accept and
// reject the same values, the batch content hash text and the metadata follow the sorted
// canonical text, and the help states the presets' defaults. (A new setting: test_setting_declaration.cpp.)
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/batch/config.h>
#include <npf/converter/convert_settings_table.h>
#include <npf/core/number_text.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace {

using namespace npf;
namespace batch = npf::batch;
using npf::testing::contains;

// The hash text of the production preset for an isotropic source (content hash version 2: the
// canonical text's lines, sorted by key).
const char* const kProductionIsotropicHashText =
    "acceleration=anderson\ncompress_rgb=false\ncompressive=1\nepsilon=0.01\nerror_pairs=20000\ng_grid=90,1\n"
    "g_pin=0.01\ng_prior=smith-start\ngrid=90,1,90,180\nimportance=2\nisotropy=auto\niterations=200\nmax_wavelengths=0\n"
    "pca=0.98999999999999999,0.98999999999999999\nphi_d_samples=0\npreset=production\nrank=0,0\n"
    "tolerance=1.0000000000000001e-05\nvolume_weight=paper\nwavelengths=\n";

batch::Settings batch_settings(const std::string& defaults) {
    const std::string dir = npf::testing::temporary_folder("settings-table");
    return batch::parse_batch_config("output_dir: out\ninputs: m.bsdf\ndefaults: " + defaults + "\n", "t.yaml", dir).materials.at(0).settings;
}

std::vector<std::string> keys_of(const std::string& text) {
    std::vector<std::string> keys;
    for (const std::string& line : npf::testing::lines_of(text)) keys.push_back(line.substr(0, line.find('=')));
    return keys;
}

TEST(SettingsTable, HashTextIsTheSortedCanonicalText) {
    EXPECT_EQ(convert_settings_hash_text(preset_settings(ConvertPreset::Production, true), true), kProductionIsotropicHashText);
    for (ConvertPreset p : {ConvertPreset::Preview, ConvertPreset::Production, ConvertPreset::Fine, ConvertPreset::Paper}) {
        for (bool iso : {true, false}) {
            const ConvertSettings s = preset_settings(p, iso);
            const std::string canonical = convert_settings_canonical_text(s), hash = convert_settings_hash_text(s, iso);
            std::vector<std::string> keys = keys_of(canonical);
            EXPECT_TRUE(std::is_sorted(keys.begin(), keys.end())) << canonical;
            // The hash's lines are the canonical text's: at a preset's values, the Always rows'.
            for (const std::string& line : npf::testing::lines_of(hash)) EXPECT_TRUE(npf::testing::has_line(canonical, line)) << line;
            keys = keys_of(hash);
            EXPECT_TRUE(std::is_sorted(keys.begin(), keys.end())) << hash;
            EXPECT_EQ(std::count(keys.begin(), keys.end(), "threads"), 0);
            EXPECT_EQ(std::count(keys.begin(), keys.end(), "detail"), 0) << "a WhenChanged row at its preset's value";
        }
    }
}

// Every setting that changes the file changes the hash, through the batch's own mapping; one
// that does not (threads) leaves it.
TEST(SettingsTable, EverySettingThatChangesTheFileChangesTheHash) {
    const ConvertSettings production = batch::resolve_convert_settings(batch_settings("{}"), true);
    const std::string base = convert_settings_hash_text(production, true);
    for (const char* d : {"{preset: preview}", "{grid: [20, 1, 18, 36]}", "{g_grid: [18, 1]}", "{pca: [0.9, 0.8]}", "{pca: [0.99, 0.99]}",
                          "{rank: [3, 2]}", "{importance: [1, 2]}", "{compressive: 0.5}", "{epsilon: 0.02}",
                          "{volume_weight: three-angle}", "{iterations: 7}", "{tolerance: 0.01}", "{g_prior: bounded}", "{plain: true}",
                          "{error_pairs: 0}", "{wavelengths: '400:700:4'}", "{max_wavelengths: 8}", "{isotropy: isotropic}",
                          "{phi_d_samples: 4}", "{pca_rule: total}", "{detail: none}", "{detail_energy: 3}", "{horizon: open}",
                          "{detail_weight: 1}", "{detail_measure: solid-angle}", "{detail_clamp_passes: 2}", "{detail_views: [0, 40]}",
                          "{no_predict: true}", "{light: studio}", "{target_psnr: 40, target_grids: 16x8x16}"}) {
        const ConvertSettings c = batch::resolve_convert_settings(batch_settings(d), true);
        EXPECT_NE(convert_settings_hash_text(c, true), base) << d;
    }
    EXPECT_EQ(convert_settings_hash_text(batch::resolve_convert_settings(batch_settings("{threads: 3}"), true), true), base);
    // Restating a preset's value is no change.
    EXPECT_EQ(convert_settings_hash_text(batch::resolve_convert_settings(batch_settings("{detail: [32, 24, 16], iterations: 200}"), true), true),
              base);
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
    // Written by convert.cpp by hand before the detail rows had metadata.
    m.emplace_back("compression_rule", s.compression.per_channel ? "per-channel" : "total");
    if (!s.detail.grid.empty()) {
        const DetailOptions& d = s.detail;
        m.emplace_back("detail_grid", std::to_string(d.grid.theta_h) + "x" + std::to_string(d.grid.theta_d) + "x" + std::to_string(d.grid.phi_d));
        m.emplace_back("detail_samples_per_cell", std::to_string(d.samples_per_cell));
        m.emplace_back("detail_display_power", six(d.display_power));
        m.emplace_back("detail_energy_weight", six(d.energy_weight));
        m.emplace_back("detail_measure", d.measure == DetailOptions::Measure::SolidAngle ? "solid-angle" : "half-angle");
        m.emplace_back("detail_clamp_passes", std::to_string(d.clamp_passes));
    }
    // Now sorted by key (the order of the file's npf:metadata_keys).
    std::sort(m.begin(), m.end());
    return m;
}

TEST(SettingsTable, MetadataLinesAreThoseBeforeSortedByKey) {
    for (ConvertPreset preset : {ConvertPreset::Preview, ConvertPreset::Production, ConvertPreset::Fine, ConvertPreset::Paper}) {
        for (bool isotropic : {true, false}) {
            ConvertSettings s = preset_settings(preset, isotropic);
            EXPECT_EQ(convert_settings_metadata(s), legacy_metadata(s)) << convert_preset_name(preset);
            s.fit.importance_power_light = 2.5;
            s.fit.acceleration = AwlsOptions::Acceleration::Anderson;
            s.fit.phi_d_samples = 0;
            s.error_pairs = 0;
            s.detail.grid = DetailGrid{};
            EXPECT_EQ(convert_settings_metadata(s), legacy_metadata(s)) << convert_preset_name(preset);
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
