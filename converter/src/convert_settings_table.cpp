#include <npf/converter/convert_settings_table.h>

#include "convert_settings_rows.h"

#include <npf/core/channels.h>
#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/core/text.h>
#include <npf/render/lighting.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace npf {

namespace {

using namespace settings_rows;

ConvertSettingsTable make_table() {
    ConvertSettingsTable t;
    add_source_rows(t);
    add_grid_rows(t);
    add_weight_rows(t);
    add_detail_rows(t);
    add_output_rows(t);
    return t;
}

}  // namespace

const ConvertSettingsTable& convert_settings_table() {
    static const ConvertSettingsTable table = make_table();
    return table;
}

const ConvertSettingRow* find_setting(const ConvertSettingsTable& table, const std::string& key) {
    for (const ConvertSettingRow& row : table) {
        if (row.key == key) return &row;
    }
    return nullptr;
}

std::string setting_flag(const ConvertSettingRow& row) {
    std::string flag = "--" + row.key;
    std::replace(flag.begin(), flag.end(), '_', '-');
    return flag;
}

SettingValue check_setting(const ConvertSettingRow& row, const std::string& v, const std::string& what) {
    SettingValue out;
    out.text = v;
    switch (row.kind) {
    case SettingKind::Switch:
        if (v != "true" && v != "false") throw Error(what, "expects true or false, got '" + v + "'");
        out.on = v == "true";
        break;
    case SettingKind::Choice:
        if (std::find(row.choices.begin(), row.choices.end(), v) == row.choices.end()) {
            throw Error(what, "'" + v + "' is not one of " + join(row.choices, ", "));
        }
        break;
    case SettingKind::Text:
        if (row.check) row.check(v, what);
        break;
    case SettingKind::Whole:
    case SettingKind::Number: {
        const std::vector<std::string> parts = split(v, ',');
        if (parts.size() < row.least_parts || (row.most_parts > 0 && parts.size() > row.most_parts)) {
            const std::size_t most = row.most_parts > 0 ? row.most_parts : row.least_parts;
            throw Error(what, "expects " + std::to_string(most) + " values" +
                                  (row.least_parts < most ? " (or " + std::to_string(row.least_parts) + ")" : std::string()) +
                                  ", got '" + v + "'");
        }
        for (std::size_t i = 0; i < parts.size(); ++i) {
            const std::string& p = parts[i];
            const std::optional<Range> range =
                row.ranges.empty() ? std::nullopt : std::optional<Range>(row.ranges[std::min(i, row.ranges.size() - 1)]);
            const auto inside = [&](double d) {
                return !range || ((range->low_open ? d > range->low : d >= range->low) && d <= range->high);
            };
            if (row.kind == SettingKind::Whole) {
                const std::string problem = "needs a whole number in " + (range ? range_text(*range) : "[0, 4294967295]") + ", got '" + p + "'";
                std::uint64_t n = 0;
                try {
                    n = parse_whole_number(p, 0, std::numeric_limits<std::uint32_t>::max(), what);
                } catch (const Error&) {
                    throw Error(what, problem);  // the row's range, not the parser's
                }
                if (!inside(double(n))) throw Error(what, problem);
                out.numbers.push_back(double(n));
            } else {
                const double d = parse_finite_number(p, what);
                if (!inside(d)) throw Error(what, row.range_problem.empty() ? "must lie in " + range_text(*range) : row.range_problem);
                out.numbers.push_back(d);
            }
        }
        break;
    }
    }
    return out;
}

std::string setting_default(const ConvertSettingRow& row, ConvertPreset preset, bool isotropic) {
    return row.read(preset_settings(preset, isotropic));
}

namespace {

// A preset's value as help shows it: numbers as short as they read back ("0.99", not the hash's
// 17 digits), and "unset" for a value the setting would refuse (a rank of 0: --pca decides).
std::string help_value(const ConvertSettingRow& row, const std::string& value) {
    try {
        if (value.empty()) return "unset";
        check_setting(row, value, row.key);
    } catch (const Error&) {
        return "unset";
    }
    const std::optional<std::vector<double>> numbers = parse_number_list(value);
    if (!numbers) return value;
    std::string text;
    for (double v : *numbers) text += (text.empty() ? "" : ",") + exact_number_text(v);
    return text;
}

}  // namespace

std::string setting_help(const ConvertSettingRow& row) {
    if (!row.read || row.kind == SettingKind::Switch) return row.help;
    const std::string production = help_value(row, setting_default(row, ConvertPreset::Production, true));
    std::string others;
    if (row.key != "preset") {  // every preset names itself
        for (const ConvertPreset p : {ConvertPreset::Preview, ConvertPreset::Fine, ConvertPreset::Paper}) {
            const std::string v = help_value(row, setting_default(row, p, true));
            if (v != production) others += std::string("; ") + convert_preset_name(p) + ": " + v;
        }
        const std::string anisotropic = help_value(row, setting_default(row, ConvertPreset::Production, false));
        if (anisotropic != production) others += "; production for anisotropic sources: " + anisotropic;
    }
    if (production == "unset" && others.empty()) return row.help;  // the help says what unset means
    return row.help + " (default: " + production + others + ")";
}

ConvertSettings resolve_convert_settings(const ConvertSettingsTable& table,
                                         const std::function<std::optional<SettingValue>(const ConvertSettingRow&)>& given,
                                         const std::function<std::string(const ConvertSettingRow&)>& name_of,
                                         bool source_isotropic) {
    std::vector<std::optional<SettingValue>> values;
    for (const ConvertSettingRow& row : table) values.push_back(given(row));
    const auto value_of = [&](const std::string& key) -> const std::optional<SettingValue>* {
        for (std::size_t i = 0; i < table.size(); ++i) {
            if (table[i].key == key) return &values[i];
        }
        return nullptr;
    };
    const auto has = [&](const std::string& key) {
        const std::optional<SettingValue>* v = value_of(key);
        return v && v->has_value();
    };
    const auto name = [&](const std::string& key) { return name_of(*find_setting(table, key)); };

    // The target chooses the detail grid, by the prediction.
    if (has("target_psnr")) {
        if (has("detail")) throw Error(name("target_psnr"), "chooses the detail grid itself; leave out " + name("detail"));
        const std::optional<SettingValue>* no_predict = value_of("no_predict");
        if (no_predict && no_predict->has_value() && (*no_predict)->on) {
            throw Error(name("target_psnr"), "needs the prediction; leave out " + name("no_predict"));
        }
    } else if (has("target_grids")) {
        throw Error(name("target_grids"), "needs " + name("target_psnr"));
    }

    // Isotropy decides the preset's grids; every other row then goes over the preset's values.
    Isotropy isotropy = Isotropy::Auto;
    if (has("isotropy")) {
        const std::string& v = (*value_of("isotropy"))->text;
        isotropy = v == "isotropic" ? Isotropy::Isotropic : v == "anisotropic" ? Isotropy::Anisotropic : Isotropy::Auto;
    }
    const bool isotropic = isotropy == Isotropy::Auto ? source_isotropic : isotropy == Isotropy::Isotropic;
    const ConvertPreset preset = has("preset") ? parse_convert_preset((*value_of("preset"))->text, name("preset")) : ConvertPreset::Production;
    ConvertSettings s = preset_settings(preset, isotropic);
    s.isotropy = isotropy;
    for (std::size_t i = 0; i < table.size(); ++i) {
        if (values[i]) table[i].apply(s, *values[i]);
    }
    return s;
}

std::string convert_settings_hash_text(const ConvertSettings& s, bool isotropic, const ConvertSettingsTable& table) {
    std::vector<const ConvertSettingRow*> always;
    for (const ConvertSettingRow& row : table) {
        if (row.hash == SettingHash::Always) always.push_back(&row);
    }
    std::stable_sort(always.begin(), always.end(), [](const ConvertSettingRow* a, const ConvertSettingRow* b) { return a->hash_order < b->hash_order; });
    std::string t;
    for (const ConvertSettingRow* row : always) t += row->hash_lines ? row->hash_lines(s) : row->key + "=" + row->read(s) + "\n";
    const ConvertSettings preset = preset_settings(s.preset, isotropic);
    for (const ConvertSettingRow& row : table) {
        if (row.hash != SettingHash::WhenChanged) continue;
        const std::string value = row.read(s);
        if (value != row.read(preset)) t += row.key + "=" + value + "\n";
    }
    return t;
}

std::vector<std::pair<std::string, std::string>> convert_settings_metadata(const ConvertSettings& fitted, int first, int last,
                                                                          const ConvertSettingsTable& table) {
    std::vector<const Row*> rows;
    for (const Row& r : table) {
        if (r.metadata && r.metadata_order >= first && r.metadata_order <= last) rows.push_back(&r);
    }
    std::stable_sort(rows.begin(), rows.end(), [](const Row* a, const Row* b) { return a->metadata_order < b->metadata_order; });
    Lines lines;
    for (const Row* r : rows) {
        for (auto& line : r->metadata(fitted)) lines.push_back(std::move(line));
    }
    return lines;
}

}  // namespace npf
