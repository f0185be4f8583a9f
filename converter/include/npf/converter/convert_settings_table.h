// The conversion settings, one row each: `npf convert`'s flags and their help, the batch
// configuration's keys, their checks, the batch content hash text and how each is applied to
// ConvertSettings all read this table, so that a new setting is one row (issue 18).
#pragma once

#include <npf/converter/convert.h>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace npf {

enum class SettingKind {
    Whole,   // whole numbers, comma-separated parts each in its range
    Number,  // finite numbers, the same
    Choice,  // one of `choices`
    Switch,  // a flag without a value (--plain); in a batch configuration true or false
    Text,    // checked by the row's `check`
};

// How a setting enters the batch content hash text (convert_settings_hash_text).
enum class SettingHash {
    Always,       // its lines at `hash_order`: the text of content hash version 1
    WhenChanged,  // "key=value" after those, only where it differs from the preset's value, so
                  // that adding a setting keeps every earlier output up to date
    Never,        // does not change the file (threads; see also target_psnr's row)
};

// A value as checked: its text, and for Whole and Number its parts; for Switch `on`.
struct SettingValue {
    std::string text;
    std::vector<double> numbers;
    bool on = false;
};

struct ConvertSettingRow {
    std::string key;  // the batch key; the flag is "--" + key with '-' for '_' (setting_flag)
    SettingKind kind = SettingKind::Text;
    // Whole, Number: how many comma-separated parts (most_parts 0: any number).
    std::size_t least_parts = 1, most_parts = 1;
    // Whole, Number: each part's range, by position (the last one for the parts beyond); none:
    // any finite number. `range_problem` replaces the generic message (Number only).
    struct Range {
        double low, high;
        bool low_open = false;
    };
    std::vector<Range> ranges;
    std::string range_problem;
    std::vector<std::string> choices;  // Choice
    // Text: throws npf::Error(what, problem) for a bad value.
    std::function<void(const std::string& text, const std::string& what)> check;
    std::string help;  // `npf convert --help`
    SettingHash hash = SettingHash::WhenChanged;
    int hash_order = 0;            // Always rows: the position of their lines
    bool changes_output = true;    // false: threads (the fit is the same on any count)
    bool takes_list = false;       // a batch value may be a YAML sequence, joined by commas
    std::function<void(ConvertSettings&, const SettingValue&)> apply;
    // The value in the row's own syntax ("90,1,90,180", "smith"), from resolved settings.
    std::function<std::string(const ConvertSettings&)> read;
    // Always rows whose hash lines are not "key=read\n" (content hash version 1's own names).
    std::function<std::string(const ConvertSettings&)> hash_lines;
    // Its lines in a factor texture's metadata (npf:meta:KEY = VALUE) from the settings as
    // fitted (after isotropy), in `metadata_order` among the rows (convert_settings_metadata);
    // none where empty or where it gives none.
    int metadata_order = 0;
    std::function<std::vector<std::pair<std::string, std::string>>(const ConvertSettings&)> metadata;
};

using ConvertSettingsTable = std::vector<ConvertSettingRow>;

// The settings, in the order of `npf convert --help`.
const ConvertSettingsTable& convert_settings_table();
// The row of `key` in `table`, or nullptr.
const ConvertSettingRow* find_setting(const ConvertSettingsTable& table, const std::string& key);

// "--error-pairs" for "error_pairs".
std::string setting_flag(const ConvertSettingRow& row);

// Checks `text` (a Switch's "true"/"false") against the row; throws npf::Error(what, problem).
SettingValue check_setting(const ConvertSettingRow& row, const std::string& text, const std::string& what);

// The value a preset gives the setting, for a source that is isotropic or not.
std::string setting_default(const ConvertSettingRow& row, ConvertPreset preset, bool isotropic);

// The row's help with its defaults read from the presets themselves (setting_default), so that
// the text cannot drift from the code: "... (default: 0.4)", or "(default: 32,24,16; preview:
// 16,8,16; paper: none)" where presets differ, and "anisotropic sources: ..." where that differs.
std::string setting_help(const ConvertSettingRow& row);

// The settings given (`given` returns the checked value of a row, or nothing), over the preset's
// (after `isotropy`) for the source; errors name each row by `name_of`. Also checks the settings
// that go together (--target-psnr with --detail, --no-predict, --target-grids).
ConvertSettings resolve_convert_settings(const ConvertSettingsTable& table,
                                         const std::function<std::optional<SettingValue>(const ConvertSettingRow&)>& given,
                                         const std::function<std::string(const ConvertSettingRow&)>& name_of,
                                         bool source_isotropic);

// The resolved settings as the batch content hash holds them, one "name=value" per line
// (docs/batch.md); `isotropic`: the fitted factors' (WhenChanged rows compare with that preset).
std::string convert_settings_hash_text(const ConvertSettings& settings, bool isotropic,
                                       const ConvertSettingsTable& table = convert_settings_table());

// The metadata lines of the rows whose metadata_order is in [first, last], in that order
// (convert_material writes its results between such runs: the file's order of keys is its
// bytes).
std::vector<std::pair<std::string, std::string>> convert_settings_metadata(
    const ConvertSettings& fitted, int first, int last, const ConvertSettingsTable& table = convert_settings_table());

}  // namespace npf
