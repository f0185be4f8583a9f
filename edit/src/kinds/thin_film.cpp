// thin_film: a dielectric film on the material, by the Airy reflectance (thin_film.h). Its base
// comes from --film-base and its mode from --film-mode on the command line, settings of every
// --thin-film step.
#include "recipe_values.h"

#include "../tables.h"

#include <npf/materials/data_files.h>
#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/edit/edit_kinds.h>
#include <npf/edit/recipe.h>

#include <cmath>
#include <cstdlib>
#include <optional>

namespace npf::edit {

FilmBase parse_film_base(const std::string& text, const std::string& what) {
    FilmBase b;
    if (text == "fitted" || text.empty()) return b;
    b.fitted = false;
    // "eta" or "eta,k"
    const std::optional<std::vector<double>> list = parse_number_list(text);
    const std::vector<double> parts = list ? *list : std::vector<double>{};
    if (list && (parts.size() == 1 || parts.size() == 2)) {
        if (!(parts[0] > 0.0) || (parts.size() == 2 && parts[1] < 0.0)) {
            throw Error(what, "'" + text + "': eta must be positive and k >= 0");
        }
        b.eta = color::SampledSpectrum::constant(parts[0]);
        b.k = color::SampledSpectrum::constant(parts.size() == 2 ? parts[1] : 0.0);
        b.label = parts.size() == 2 ? "eta " + number_text(parts[0]) + " + " + number_text(parts[1]) + "i" : "dielectric " + number_text(parts[0]);
        return b;
    }
    if (list) throw Error(what, "'" + text + "' is neither fitted, eta, eta,k nor a metal name");
    const std::string eta = find_data_file("ior/" + text + ".eta.spd"), k = find_data_file("ior/" + text + ".k.spd");
    if (eta.empty() || k.empty()) {
        throw Error(what, "'" + text + "' is neither fitted, a number, eta,k nor a metal of the shipped tables (Ag, Al, Au, Cr, Cu)");
    }
    b.eta = color::read_spd(eta);
    b.k = color::read_spd(k);
    b.label = text;
    return b;
}

namespace kinds {

namespace {

struct Film {
    ThinFilm film;
    std::string index_named;  // the film's index as the label names it
};

std::optional<FilmMode> film_mode_named(const std::string& name) {
    if (name == "ratio") return FilmMode::Ratio;
    if (name == "replace") return FilmMode::Replace;
    return std::nullopt;
}

// A fixed index or {eta: ..., k: ...} spectra.
FilmBase recipe_base(const YamlContext& cx, const YAML::Node& node) {
    if (node.IsScalar()) return cx.at(node, "base", [&] { return parse_film_base(node.Scalar(), "base"); });
    cx.only(node, "base", {"eta", "k"});
    if (!node["eta"]) cx.fail(node, "base", "missing 'eta'");
    FilmBase b;
    b.fitted = false;
    b.eta = cx.spectrum(node["eta"], "eta");
    if (node["k"]) b.k = cx.spectrum(node["k"], "k");
    b.label = "given index";
    return b;
}

Film read_recipe(const YamlContext& cx, const YAML::Node& v) {
    cx.only(v, "thin_film", {"thickness", "film_ior", "base", "mode"});
    if (!v["thickness"]) cx.fail(v, "thin_film", "missing 'thickness' (nm)");
    if (!v["film_ior"]) cx.fail(v, "thin_film", "missing 'film_ior'");
    Film f;
    f.film.thickness_nm = cx.number(v["thickness"], "thickness");
    if (f.film.thickness_nm < 0.0) cx.fail(v["thickness"], "thickness", "must not be negative (nm)");
    f.film.film_eta = cx.spectrum(v["film_ior"], "film_ior");
    for (double x : f.film.film_eta.values()) {
        if (!(x > 0.0)) cx.fail(v["film_ior"], "film_ior", "indices are positive");
    }
    if (v["base"]) f.film.base = recipe_base(cx, v["base"]);
    if (v["mode"]) {
        const std::string mode = cx.text(v["mode"], "mode");
        const std::optional<FilmMode> m = film_mode_named(mode);
        if (!m) cx.fail(v["mode"], "mode", "'" + mode + "' is not ratio or replace");
        f.film.mode = *m;
    }
    f.index_named = v["film_ior"].IsScalar() ? v["film_ior"].Scalar() : std::string("(spectrum)");
    return f;
}

std::string setting(const GivenFlags& given, const std::string& flag, const std::string& fallback) {
    const auto it = given.find(flag);
    return it == given.end() ? fallback : it->second;
}

FilmBase flag_film_base(const GivenFlags& given) {
    return parse_film_base(setting(given, "--film-base", "fitted"), "--film-base");
}

FilmMode flag_film_mode(const GivenFlags& given) {
    const std::string mode = setting(given, "--film-mode", "ratio");
    const std::optional<FilmMode> m = film_mode_named(mode);
    if (!m) throw Error("--film-mode", "'" + mode + "' is not ratio or replace");
    return *m;
}

// Bad values of --film-base and --film-mode fail before any step is built.
void check_settings(const GivenFlags& given) {
    flag_film_base(given);
    flag_film_mode(given);
}

Film read_flag(const std::string& flag, const std::string& text, const GivenFlags& given) {
    const std::vector<double> p = flag_numbers(flag, text, 2);
    if (p[0] < 0.0) throw Error(flag, "the thickness (nm) must not be negative");
    if (!(p[1] > 0.0)) throw Error(flag, "the film index must be positive");
    Film f;
    f.film.thickness_nm = p[0];
    f.film.film_eta = color::SampledSpectrum::constant(p[1]);
    f.film.base = flag_film_base(given);
    f.film.mode = flag_film_mode(given);
    f.index_named = number_text(p[1]);
    return f;
}

EditStep build(const Film& f) {
    return EditStep::thin_film(f.film, "thin film " + number_text(f.film.thickness_nm) + " nm, index " + f.index_named);
}

}  // namespace

EditKind thin_film() {
    return make_edit_kind<Film>({
        "thin_film",
        {{"--thin-film", "thin film THICKNESS_NM,FILM_IOR on the material (Airy reflectance)"},
         {"--film-base", "for --thin-film: fitted (default; from the material's F), ETA, ETA,K or a metal (Ag, Al, Au, Cr, Cu)",
          true, false},
         {"--film-mode", "for --thin-film: ratio (default; keeps the measured F's shape) or replace", true, false}},
        read_recipe,
        read_flag,
        build,
        check_settings,
    });
}

}  // namespace kinds

}  // namespace npf::edit
