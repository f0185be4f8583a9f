// The conversion settings, one row each: `npf convert`'s flags and their help, the batch
// configuration's keys, their checks, the presets (key=value lines applied through the rows),
// the batch content hash text and the factor texture's settings metadata all read this table.
// Each row is declared beside the code that uses it (converter/src/settings/: the fitter's, the
// detail layer's, the source's and the outputs'), so that a new setting is one declaration
// there, or a SettingRegistration anywhere else (issue 36).
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
    Always,       // its "key=value" line, whatever the value
    WhenChanged,  // its line only where it differs from the preset's value, so that adding a
                  // setting keeps every earlier output up to date (the default for a new row)
    Never,        // does not change the file (threads; see also target_psnr's row), or another
                  // row's line holds what it sets (plain: acceleration)
};

// The groups of `npf convert --help`, in its order.
enum class SettingGroup { Source, Grid, Weights, Detail, Output };

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
    bool changes_output = true;    // false: threads (the fit is the same on any count)
    // Set by the presets alone (the paper preset's line search, the preview's smaller
    // prediction): no flag, no batch key, no help; still in the hash text and the metadata.
    bool preset_only = false;
    bool takes_list = false;       // a batch value may be a YAML sequence, joined by commas
    std::function<void(ConvertSettings&, const SettingValue&)> apply;
    // The value in the row's own syntax ("90,1,90,180", "smith"), from resolved settings: what
    // `apply` reads back to the same settings (the canonical text, the presets' defaults).
    std::function<std::string(const ConvertSettings&)> read;
    // Its lines in a factor texture's metadata (npf:meta:KEY = VALUE) from the settings as
    // fitted (after isotropy; the detail grid the one written); none where empty or where it
    // gives none (convert_settings_metadata sorts them by key).
    std::function<std::vector<std::pair<std::string, std::string>>(const ConvertSettings&)> metadata;
};

using ConvertSettingsTable = std::vector<ConvertSettingRow>;

// Declares a setting from outside the converter's own files (a plug-in, a test): while the
// object lives, `row` is in the table at the end of its group, and in the hash text and the
// metadata. Make it before any thread reads the table (at static initialisation, or in a
// test's body); a reference to the table is good until the next registration ends or begins.
class SettingRegistration {
public:
    SettingRegistration(SettingGroup group, ConvertSettingRow row);
    ~SettingRegistration();
    SettingRegistration(const SettingRegistration&) = delete;
    SettingRegistration& operator=(const SettingRegistration&) = delete;

private:
    std::size_t m_id;
};

// The settings a user may give, in the order of `npf convert --help` (the groups in order, the
// rows of a group as their file declares them).
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

// The canonical text of resolved settings: every row's "key=value" line (the presets' own rows
// included), sorted by key. The hash text and the metadata follow its order.
std::string convert_settings_canonical_text(const ConvertSettings& settings);

// The resolved settings as the batch content hash holds them (docs/batch.md): the canonical
// text's lines of the rows that enter it (SettingHash); `isotropic`: the fitted factors'
// (WhenChanged rows compare with that preset).
std::string convert_settings_hash_text(const ConvertSettings& settings, bool isotropic);

// The settings' metadata lines of a factor texture, sorted by key (the file's order of keys is
// its bytes: docs/format.md).
std::vector<std::pair<std::string, std::string>> convert_settings_metadata(const ConvertSettings& fitted);

}  // namespace npf
