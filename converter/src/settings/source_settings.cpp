// What is fitted: the preset, the channels, the isotropy (convert.cpp's choose_channels and
// resolve_convert_settings read them).
#include "setting_rows.h"

#include <npf/core/channels.h>

namespace npf::settings_rows {

Rows source_settings() {
    Rows rows;
    Row r;

    r = always_hashed(choice("preset", {"preview", "production", "fine", "paper"},
                             "preview, production, fine or paper (the paper's pure model; docs/fitting.md)"));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.preset = parse_convert_preset(v.text, "preset"); };
    r.read = [](const ConvertSettings& s) { return std::string(convert_preset_name(s.preset)); };
    r.metadata = [](const ConvertSettings& s) { return Lines{{"preset", convert_preset_name(s.preset)}}; };
    rows.push_back(r);

    r = always_hashed(text("wavelengths", [](const std::string& v, const std::string& what) { parse_channel_list(v, what); },
                           "channels to fit: rgb, start:end:count or a,b,c nm (unset: the source's own)"));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.wavelengths = v.text; };
    r.read = [](const ConvertSettings& s) { return s.wavelengths; };
    rows.push_back(r);

    r = always_hashed(whole("max_wavelengths", {{0, 100000}}, "keep at most this many of the source's wavelengths, evenly spread (0: all)"));
    r.apply = [](ConvertSettings& s, const SettingValue& v) { s.max_wavelengths = int(v.numbers[0]); };
    r.read = [](const ConvertSettings& s) { return std::to_string(s.max_wavelengths); };
    rows.push_back(r);

    // Also read before the preset: it decides the preset's grids (resolve_convert_settings).
    r = always_hashed(choice("isotropy", {"auto", "isotropic", "anisotropic"}, "auto (as the source), isotropic or anisotropic"));
    r.apply = [](ConvertSettings& s, const SettingValue& v) {
        s.isotropy = v.text == "isotropic" ? Isotropy::Isotropic : v.text == "anisotropic" ? Isotropy::Anisotropic : Isotropy::Auto;
    };
    r.read = [](const ConvertSettings& s) {
        return std::string(s.isotropy == Isotropy::Isotropic ? "isotropic" : s.isotropy == Isotropy::Anisotropic ? "anisotropic" : "auto");
    };
    rows.push_back(r);
    return rows;
}

}  // namespace npf::settings_rows
