// The settings of a material: checking their values, resolving them into the converter's and
// the validation renders' settings, and the canonical text the content hash takes.
#include <npf/batch/config.h>

#include "setting_values.h"

#include <npf/converter/convert_settings_table.h>
#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/render/lighting.h>
#include <npf/render/render_settings.h>

#include <optional>

namespace npf::batch {

namespace {

// render.KEY's declaration (render_settings.h, shared with `npf render`'s flags), or null for a
// key that is not a whole number (env).
const render::WholeRenderSetting* render_setting(const std::string& setting) {
    static const render::WholeRenderSetting* const all[] = {&render::kSideSetting, &render::kSppSetting, &render::kSeedSetting,
                                                            &render::kThreadsSetting};
    for (const render::WholeRenderSetting* s : all)
        if (setting == std::string("render.") + s->name) return s;
    return nullptr;
}

}  // namespace

namespace detail {

void bad(const std::string& origin, const std::string& key, const std::string& problem) {
    throw Error(origin, "key '" + key + "': " + problem);
}

bool boolean(const std::string& origin, const std::string& key, const std::string& v) {
    if (v == "true") return true;
    if (v == "false") return false;
    bad(origin, key, "expects true or false, got '" + v + "'");
}


void check_value(const std::string& origin, const std::string& key, const std::string& setting, const std::string& v) {
    if (setting == "render") {
        boolean(origin, key, v);
        return;
    }
    try {
        if (const ConvertSettingRow* row = find_setting(convert_settings_table(), setting)) check_setting(*row, v, key);
        else if (const render::WholeRenderSetting* r = render_setting(setting)) r->parse(v, key);
        else if (setting == "memory_limit") parse_memory_limit(v, key);
        else if (setting == "time_limit") parse_time_limit(v, key);
        // edit and render.env are paths, checked when used.
    } catch (const Error& e) {
        bad(origin, key, e.problem());
    }
}

const std::vector<std::string>& render_keys() {
    static const std::vector<std::string> keys = {"size", "spp", "seed", "env", "threads"};
    return keys;
}

}  // namespace detail

using detail::bad;
using detail::check_value;

const std::vector<std::string>& setting_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const ConvertSettingRow& row : convert_settings_table()) n.push_back(row.key);
        for (const char* batch_only : {"memory_limit", "time_limit", "edit", "render"}) n.emplace_back(batch_only);
        for (const std::string& k : detail::render_keys()) n.push_back("render." + k);
        return n;
    }();
    return names;
}

ConvertSettings resolve_convert_settings(const Settings& s, bool source_isotropic) {
    for (const auto& [k, v] : s) check_value(v.origin, k, k, v.value);
    const ConvertSettingsTable& table = convert_settings_table();
    try {
        return resolve_convert_settings(
            table,
            [&](const ConvertSettingRow& row) -> std::optional<SettingValue> {
                const auto it = s.find(row.key);
                if (it == s.end()) return std::nullopt;
                return check_setting(row, it->second.value, row.key);
            },
            [](const ConvertSettingRow& row) { return row.key; }, source_isotropic);
    } catch (const Error& e) {
        // Settings that do not go together: named by the first one's origin and key.
        const auto it = s.find(e.source());
        if (it == s.end()) throw;
        bad(it->second.origin, it->first, e.problem());
    }
}


RenderCheck resolve_render_check(const Settings& s) {
    RenderCheck r;
    const auto it = s.find("render");
    r.enabled = it != s.end() && it->second.value == "true";
    // Checked when read (check_value); read here by the same declarations.
    const auto whole_of = [&s](const render::WholeRenderSetting& setting, std::uint64_t fallback) {
        const auto i = s.find(std::string("render.") + setting.name);
        return i == s.end() ? fallback : setting.parse(i->second.value, i->first);
    };
    r.size = std::size_t(whole_of(render::kSideSetting, r.size));
    r.spp = std::uint32_t(whole_of(render::kSppSetting, r.spp));
    r.seed = whole_of(render::kSeedSetting, r.seed);
    r.threads = unsigned(whole_of(render::kThreadsSetting, r.threads));
    if (const auto i = s.find("render.env"); i != s.end()) r.lightings = render::parse_lighting_list(i->second.value, "render.env");
    else if (const auto l = s.find("light"); l != s.end()) r.lightings = render::parse_lighting_list(l->second.value, "light");
    else r.lightings = render::builtin_lighting_names();
    return r;
}

std::string canonical_settings(const Settings& settings) {
    std::string text;
    for (const auto& [k, v] : settings) {
        const ConvertSettingRow* row = find_setting(convert_settings_table(), k);
        if ((row && !row->changes_output) || k == "memory_limit" || k == "time_limit" || k == "edit" || k == "render" ||
            k.rfind("render.", 0) == 0)
            continue;
        text += k + "=" + v.value + "\n";
    }
    return text;
}

}  // namespace npf::batch
