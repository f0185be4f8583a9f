// diffuse: the diffuse colour replaced by another material's rho_d, an albedo spectrum or an
// albedo colour (colour_edits.h).
#include "recipe_values.h"

#include "../tables.h"

#include <npf/core/number_text.h>
#include <npf/core/error.h>
#include <npf/edit/edit_kinds.h>

namespace npf::edit::kinds {

namespace {

struct DiffuseSource {
    enum class From { Material, Spectrum, Colour };
    From from = From::Material;
    std::string path;                 // Material
    color::SampledSpectrum spectrum;  // Spectrum
    color::Rgb colour{};              // Colour, as given
    bool srgb_encoded = false;        // Colour
    // The spectrum or the colour as the label names it: a flag's text as typed, the recipe's
    // numbers (a recipe's spectrum is "a spectrum").
    std::string named;
    double scale = 1.0;
};

DiffuseSource read_recipe(const YamlContext& cx, const YAML::Node& v) {
    cx.only(v, "diffuse", {"from", "srgb", "linear_srgb", "spectrum", "scale"});
    int sources = 0;
    for (const char* k : {"from", "srgb", "linear_srgb", "spectrum"}) sources += v[k] ? 1 : 0;
    if (sources != 1) cx.fail(v, "diffuse", "give exactly one of from, srgb, linear_srgb, spectrum");
    DiffuseSource d;
    d.scale = detail::recipe_scale(cx, v);
    if (v["from"]) {
        d.path = cx.path(v["from"], "from");
    } else if (v["spectrum"]) {
        d.from = DiffuseSource::From::Spectrum;
        d.spectrum = cx.spectrum(v["spectrum"], "spectrum");
        for (double x : d.spectrum.values()) {
            if (x < 0.0) cx.fail(v["spectrum"], "spectrum", "albedo values are >= 0");
        }
        d.named = "a spectrum";
    } else {
        d.from = DiffuseSource::From::Colour;
        d.srgb_encoded = bool(v["srgb"]);
        d.colour = detail::recipe_rgb(cx, d.srgb_encoded ? v["srgb"] : v["linear_srgb"], d.srgb_encoded ? "srgb" : "linear_srgb");
        d.named = number_text(d.colour[0], 4) + ", " + number_text(d.colour[1], 4) + ", " + number_text(d.colour[2], 4);
    }
    return d;
}

DiffuseSource read_flag(const std::string& flag, const std::string& text, const GivenFlags&) {
    DiffuseSource d;
    d.named = text;
    if (flag == "--diffuse-from") {
        d.path = text;
    } else if (flag == "--diffuse-spectrum") {
        d.from = DiffuseSource::From::Spectrum;
        d.spectrum = color::read_spd(text);
    } else {
        d.from = DiffuseSource::From::Colour;
        d.srgb_encoded = flag == "--diffuse-srgb";
        const std::vector<double> c = flag_numbers(flag, text, 3);
        for (std::size_t i = 0; i < 3; ++i) {
            if (c[i] < 0.0) throw Error(flag, "colour components are >= 0, got '" + text + "'");
            d.colour[i] = c[i];
        }
    }
    return d;
}

EditStep build(const DiffuseSource& d) {
    const std::string scaled = d.scale != 1.0 ? " x " + number_text(d.scale) : "";
    switch (d.from) {
    case DiffuseSource::From::Material:
        return EditStep::diffuse_from(d.path, d.scale);
    case DiffuseSource::From::Spectrum: {
        color::SampledSpectrum albedo = d.spectrum;
        if (d.scale != 1.0) {
            std::vector<double> values = albedo.values();
            for (double& x : values) x *= d.scale;
            albedo = color::SampledSpectrum(albedo.wavelengths(), values);
        }
        return EditStep::diffuse_albedo(albedo, "diffuse albedo from " + d.named + scaled);
    }
    case DiffuseSource::From::Colour:
        break;
    }
    color::Rgb linear = d.colour;
    if (d.srgb_encoded) {
        for (double& x : linear) x = color::srgb_to_linear(x);
    }
    for (double& x : linear) x *= d.scale;
    return EditStep::diffuse_albedo(linear, std::string("diffuse albedo ") + (d.srgb_encoded ? "sRGB" : "linear sRGB") + " (" +
                                                d.named + ")" + scaled);
}

}  // namespace

EditKind diffuse() {
    return make_edit_kind<DiffuseSource>({
        "diffuse",
        {{"--diffuse-from", "rho_d of another NPF material (.exr, isotropic or anisotropic)"},
         {"--diffuse-srgb", "diffuse albedo R,G,B as sRGB-encoded values in [0, 1] (rho_d = albedo / pi)"},
         {"--diffuse-linear", "diffuse albedo R,G,B in linear sRGB"},
         {"--diffuse-spectrum", "diffuse albedo spectrum from a .spd file (nm, value)"}},
        read_recipe,
        read_flag,
        build,
    });
}

}  // namespace npf::edit::kinds
