#include <npf/converter/convert_settings_table.h>

#include "settings/setting_rows.h"

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
#include <iterator>
#include <limits>
#include <mutex>
#include <stdexcept>

namespace npf {

namespace settings_rows {

namespace {

// The groups' own rows, in the order of `npf convert --help` (the golden reference pins it): one
// list, indexed by SettingGroup. A static library drops a file nothing refers to, so the
// converter's groups are named here rather than registering themselves.
Rows (*const kGroupSettings[])() = {source_settings, fit_grid_settings, fit_weight_settings, detail_settings, output_settings};

struct Registered {
    std::size_t id;
    SettingGroup group;
    ConvertSettingRow row;
};

// The settings declared by SettingRegistration, and the tables built from them (rebuilt when a
// registration begins or ends).
struct Registry {
    std::mutex mutex;
    std::vector<Registered> registered;
    std::size_t next_id = 0, changes = 0, built = std::size_t(-1);
    ConvertSettingsTable all, user;
};

Registry& registry() {
    static Registry r;
    return r;
}

// Builds the tables under the registry's lock; the keys must be unique.
void build_tables(Registry& r) {
    if (r.built == r.changes) return;
    r.all.clear();
    r.user.clear();
    for (std::size_t g = 0; g < std::size(kGroupSettings); ++g) {
        for (Row& row : kGroupSettings[g]()) r.all.push_back(std::move(row));
        for (const Registered& extra : r.registered) {
            if (std::size_t(extra.group) == g) r.all.push_back(extra.row);
        }
    }
    for (std::size_t i = 0; i < r.all.size(); ++i) {
        for (std::size_t j = 0; j < i; ++j) {
            if (r.all[i].key == r.all[j].key) throw std::logic_error("two conversion settings are called " + r.all[i].key);
        }
        if (!r.all[i].preset_only) r.user.push_back(r.all[i]);
    }
    r.built = r.changes;
}

}  // namespace

const ConvertSettingsTable& all_settings() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    build_tables(r);
    return r.all;
}

}  // namespace settings_rows

using namespace settings_rows;

SettingRegistration::SettingRegistration(SettingGroup group, ConvertSettingRow row) {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    m_id = r.next_id++;
    r.registered.push_back({m_id, group, std::move(row)});
    ++r.changes;
}

SettingRegistration::~SettingRegistration() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    r.registered.erase(std::remove_if(r.registered.begin(), r.registered.end(), [&](const Registered& x) { return x.id == m_id; }),
                       r.registered.end());
    ++r.changes;
}

const ConvertSettingsTable& convert_settings_table() {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    build_tables(r);
    return r.user;
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
    // Asking for compression compresses RGB too (ConvertSettings::compress_rgb); a preset's
    // ratio does not.
    if (has("pca") || has("rank")) s.compress_rgb = true;
    return s;
}

namespace {

// Every row with its value's text, sorted by key: the canonical order.
std::vector<std::pair<const Row*, std::string>> canonical_values(const ConvertSettings& s) {
    std::vector<std::pair<const Row*, std::string>> values;
    for (const Row& row : all_settings()) values.emplace_back(&row, row.read(s));
    std::sort(values.begin(), values.end(), [](const auto& a, const auto& b) { return a.first->key < b.first->key; });
    return values;
}

}  // namespace

std::string convert_settings_canonical_text(const ConvertSettings& s) {
    std::string t;
    for (const auto& [row, value] : canonical_values(s)) t += row->key + "=" + value + "\n";
    return t;
}

std::string convert_settings_hash_text(const ConvertSettings& s, bool isotropic) {
    const ConvertSettings preset = preset_settings(s.preset, isotropic);
    std::string t;
    for (const auto& [row, value] : canonical_values(s)) {
        const bool in = row->hash == SettingHash::Always || (row->hash == SettingHash::WhenChanged && value != row->read(preset));
        if (in) t += row->key + "=" + value + "\n";
    }
    return t;
}

std::vector<std::pair<std::string, std::string>> convert_settings_metadata(const ConvertSettings& fitted) {
    Lines lines;
    for (const auto& value : canonical_values(fitted)) {
        if (!value.first->metadata) continue;
        for (auto& line : value.first->metadata(fitted)) lines.push_back(std::move(line));
    }
    // A row's lines are named for the file's reader (fit_grid for grid): sorted by those names.
    std::stable_sort(lines.begin(), lines.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    return lines;
}

}  // namespace npf
