#include <npf/materials/material_recipe.h>
#include <npf/core/text.h>
#include <npf/materials/analytic/analytic_brdf.h>

#include <npf/materials/data_files.h>
#include <npf/materials/yaml_context.h>
#include <npf/core/error.h>
#include <npf/core/text_input.h>
#include <npf/core/input_file.h>
#include <npf/core/number_text.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace npf {

const char* const kDefaultWavelengths = "360:1000:195";

namespace {

// Errors name the recipe, the line and the key, like "recipe.yaml:7: key 'alpha': ...".
struct Context : YamlContext {
    // The Fresnel and spectrum constructors name themselves as the source; the recipe's line and
    // key say more, so only their problem is kept (a file's name stays).
    std::string problem_of(const Error& e) const override {
        return e.source().empty() || e.source() == "Fresnel" || e.source() == "spectrum" ? e.problem()
                                                                                         : e.source() + ": " + e.problem();
    }
};

// Weights, albedos and indices: spectra whose values may not be negative.
color::SampledSpectrum parse_spectrum(const Context& cx, const YAML::Node& node, const std::string& key) {
    color::SampledSpectrum s = cx.spectrum(node, key);  // any spelling, as in edit recipes
    for (double v : s.values()) {
        if (v < 0.0) cx.fail(node, key, "negative value " + std::to_string(v) + " (weights, albedos and indices are >= 0)");
    }
    return s;
}

Fresnel parse_conductor(const Context& cx, const YAML::Node& node, const std::string& key) {
    if (node.IsScalar()) {
        const std::string metal = cx.text(node, key);
        return cx.at(node, key, [&] { return conductor_fresnel(metal, ""); });
    }
    cx.only(node, key, {"eta", "k"});
    if (!node["eta"] || !node["k"]) cx.fail(node, key, "a conductor needs both eta and k");
    const color::SampledSpectrum eta = parse_spectrum(cx, node["eta"], "eta");
    const color::SampledSpectrum k = parse_spectrum(cx, node["k"], "k");
    return cx.at(node, key, [&] { return Fresnel::conductor(eta, k); });
}

Fresnel parse_fresnel(const Context& cx, const YAML::Node& node) {
    cx.only(node, "fresnel", {"conductor", "dielectric", "schlick", "thin_film", "one"}, {"one"});
    if (node.size() != 1) cx.fail(node, "fresnel", "give exactly one of conductor, dielectric, schlick, thin_film, one");
    const auto kv = *node.begin();
    const std::string kind = kv.first.Scalar();
    const YAML::Node value = kv.second;
    if (kind == "conductor") return parse_conductor(cx, value, kind);
    if (kind == "dielectric") {
        const color::SampledSpectrum eta = parse_spectrum(cx, value, kind);
        return cx.at(value, kind, [&] { return Fresnel::dielectric(eta); });
    }
    if (kind == "schlick") {
        const color::SampledSpectrum f0 = parse_spectrum(cx, value, kind);
        return cx.at(value, kind, [&] { return Fresnel::schlick(f0); });
    }
    if (kind == "one") return Fresnel::one();
    cx.only(value, kind, {"thickness", "film_ior", "base"});
    for (const char* required : {"thickness", "film_ior", "base"}) {
        if (!value[required]) cx.fail(value, kind, std::string("missing '") + required + "'");
    }
    const double thickness = cx.number(value["thickness"], "thickness");
    if (thickness < 0.0) cx.fail(value["thickness"], "thickness", "must not be negative (nm)");
    const color::SampledSpectrum film = parse_spectrum(cx, value["film_ior"], "film_ior");
    const YAML::Node base = value["base"];
    color::SampledSpectrum base_eta, base_k = color::SampledSpectrum::constant(0.0);
    if (base.IsScalar()) {
        double eta = 0.0;
        std::istringstream is(base.Scalar());
        if (is >> eta && is.eof()) {
            base_eta = color::SampledSpectrum::constant(eta);  // a dielectric base
        } else {
            const std::string metal = base.Scalar();
            const std::string eta_path = find_data_file("ior/" + metal + ".eta.spd");
            const std::string k_path = find_data_file("ior/" + metal + ".k.spd");
            if (eta_path.empty() || k_path.empty()) cx.fail(base, "base", "no refractive index tables for metal '" + metal + "'");
            base_eta = cx.at(base, "base", [&] { return color::read_spd(eta_path); });
            base_k = cx.at(base, "base", [&] { return color::read_spd(k_path); });
        }
    } else {
        cx.only(base, "base", {"eta", "k"});
        if (!base["eta"]) cx.fail(base, "base", "missing 'eta'");
        base_eta = parse_spectrum(cx, base["eta"], "eta");
        if (base["k"]) base_k = parse_spectrum(cx, base["k"], "k");
    }
    return cx.at(value, kind, [&] { return Fresnel::thin_film(thickness, film, base_eta, base_k); });
}

SpecularLobe parse_lobe(const Context& cx, const YAML::Node& node) {
    cx.only(node, "lobes", {"distribution", "alpha", "rotation", "fresnel", "weight"});
    SpecularLobe lobe;
    if (node["distribution"]) {
        const std::string d = cx.text(node["distribution"], "distribution");
        if (d == "ggx") lobe.ndf.type = MicrofacetDistribution::Ggx;
        else if (d == "beckmann") lobe.ndf.type = MicrofacetDistribution::Beckmann;
        else cx.fail(node["distribution"], "distribution", "'" + d + "' is not ggx or beckmann");
    }
    if (!node["alpha"]) cx.fail(node, "lobes", "a lobe needs 'alpha' (one number or [alpha_x, alpha_y])");
    const YAML::Node alpha = node["alpha"];
    if (alpha.IsSequence()) {
        if (alpha.size() != 2) cx.fail(alpha, "alpha", "expected [alpha_x, alpha_y]");
        lobe.ndf.alpha_x = float(cx.number(alpha[0], "alpha"));
        lobe.ndf.alpha_y = float(cx.number(alpha[1], "alpha"));
    } else {
        lobe.ndf.alpha_x = lobe.ndf.alpha_y = float(cx.number(alpha, "alpha"));
    }
    if (!(lobe.ndf.alpha_x >= 1e-4f && lobe.ndf.alpha_y >= 1e-4f && lobe.ndf.alpha_x <= 4.f && lobe.ndf.alpha_y <= 4.f)) {
        cx.fail(alpha, "alpha", "roughness must lie in [1e-4, 4]");
    }
    if (node["rotation"]) lobe.ndf.rotation = float(cx.number(node["rotation"], "rotation") * kPiD / 180.0);
    if (node["fresnel"]) lobe.fresnel = parse_fresnel(cx, node["fresnel"]);
    if (node["weight"]) lobe.weight = parse_spectrum(cx, node["weight"], "weight");
    return lobe;
}

Channels parse_channels(const Context& cx, const YAML::Node& node) {
    if (node.IsScalar()) {
        try {
            return parse_channel_list(node.Scalar(), "wavelengths");
        } catch (const Error& e) {
            cx.fail(node, "wavelengths", e.problem());
        }
    }
    if (!node.IsSequence() || node.size() == 0) cx.fail(node, "wavelengths", "expected rgb, start:end:count or a list");
    std::vector<float> w;
    for (const YAML::Node& v : node) {
        w.push_back(float(cx.number(v, "wavelengths")));
        if (w.back() <= 0.f) cx.fail(v, "wavelengths", "wavelengths are positive (nm)");
        if (w.size() > 1 && !(w.back() > w[w.size() - 2])) cx.fail(v, "wavelengths", "wavelengths must be strictly ascending");
    }
    return Channels::spectral(w);
}

}  // namespace

color::SampledSpectrum spectrum_from_text(const std::string& text, const std::string& what) {
    const std::optional<std::vector<double>> list = parse_number_list(text);
    const std::vector<double> parts = list ? *list : std::vector<double>{};
    const bool numbers = bool(list);
    if (numbers && parts.size() == 1) return color::SampledSpectrum::constant(parts[0]);
    if (numbers && parts.size() == 3) return color::srgb_to_spectrum(parts[0], parts[1], parts[2]);
    if (numbers) throw Error(what, "'" + text + "' is neither one number nor an r,g,b colour");
    return color::read_spd(text);
}

Fresnel conductor_fresnel(const std::string& metal, const std::string& what) {
    const std::string eta = find_data_file("ior/" + metal + ".eta.spd");
    const std::string k = find_data_file("ior/" + metal + ".k.spd");
    if (eta.empty() || k.empty()) {
        throw Error(what, "no refractive index tables for metal '" + metal + "' (shipped: Ag, Al, Au, Cr, Cu)");
    }
    return Fresnel::conductor(color::read_spd(eta), color::read_spd(k));
}

MaterialRecipe parse_material_recipe(const std::string& yaml, const std::string& source, const std::string& base_dir) {
    Context cx;
    cx.source = source;
    cx.base_dir = base_dir;
    const YAML::Node root = cx.load_mapping(yaml, "a material recipe is a YAML mapping (name, lobes, diffuse, ...)");
    cx.only(root, "", {"name", "output", "wavelengths", "lobes", "diffuse", "retroreflection", "sheen", "grid",
                       "anisotropy"});
    MaterialRecipe r;
    if (root["name"]) r.material.name = cx.text(root["name"], "name");
    if (root["output"]) {
        r.output = cx.text(root["output"], "output");
        if (!r.output.empty() && r.output[0] != '/') r.output = base_dir + "/" + r.output;
    }
    // The default is the database's spectral sampling, as for `npf synth` flags.
    r.writer.channels = root["wavelengths"] ? parse_channels(cx, root["wavelengths"])
                                            : Channels::spectral(parse_wavelength_list(kDefaultWavelengths, source));
    if (!r.writer.channels.is_rgb()) r.material.wavelengths = r.writer.channels.wavelengths();
    if (root["lobes"]) {
        if (!root["lobes"].IsSequence()) cx.fail(root["lobes"], "lobes", "expected a list of lobes");
        for (const YAML::Node& lobe : root["lobes"]) r.material.specular.push_back(parse_lobe(cx, lobe));
    }
    if (root["diffuse"]) r.material.diffuse = parse_spectrum(cx, root["diffuse"], "diffuse");
    if (root["retroreflection"]) {
        const YAML::Node n = root["retroreflection"];
        cx.only(n, "retroreflection", {"weight", "exponent"});
        if (!n["weight"]) cx.fail(n, "retroreflection", "missing 'weight'");
        r.material.retroreflection = parse_spectrum(cx, n["weight"], "weight");
        if (n["exponent"]) {
            r.material.retro_exponent = float(cx.number(n["exponent"], "exponent"));
            if (r.material.retro_exponent < 0.f || r.material.retro_exponent > 1e6f) {
                cx.fail(n["exponent"], "exponent", "must lie in [0, 1e6]");
            }
        }
    }
    if (root["sheen"]) r.material.sheen = parse_spectrum(cx, root["sheen"], "sheen");
    if (r.material.specular.empty() && r.material.diffuse.empty() && r.material.retroreflection.empty() &&
        r.material.sheen.empty()) {
        throw Error(source, "the material has no lobes, no diffuse, no retroreflection and no sheen: it reflects nothing");
    }
    if (root["grid"]) {
        const YAML::Node g = root["grid"];
        cx.only(g, "grid", {"phi", "theta", "ndf", "ndf_rows", "vndf", "data"});
        if (g["phi"]) r.writer.phi_count = cx.whole(g["phi"], "phi", 3, 4096);
        if (g["theta"]) r.writer.theta_count = cx.whole(g["theta"], "theta", 2, 4096);
        if (g["ndf"]) r.writer.ndf_size = cx.whole(g["ndf"], "ndf", 2, 4096);
        if (g["ndf_rows"]) r.writer.ndf_rows = cx.whole(g["ndf_rows"], "ndf_rows", 2, 4096);
        if (g["vndf"]) r.writer.vndf_size = cx.whole(g["vndf"], "vndf", 2, 4096);
        if (g["data"]) r.writer.data_size = cx.whole(g["data"], "data", 2, 4096);
    }
    if (root["anisotropy"]) {
        const std::string a = cx.text(root["anisotropy"], "anisotropy");
        if (a == "auto") r.writer.anisotropy = AnisotropyMode::Auto;
        else if (a == "isotropic") r.writer.anisotropy = AnisotropyMode::Isotropic;
        else if (a == "anisotropic") r.writer.anisotropy = AnisotropyMode::Anisotropic;
        else cx.fail(root["anisotropy"], "anisotropy", "'" + a + "' is not auto, isotropic or anisotropic");
    }
    r.writer.description = r.material.name;
    return r;
}

MaterialRecipe load_material_recipe(const std::string& path) {
    const std::string text = read_text_file(path, "a recipe", kRecipeTextBounds);
    const std::size_t slash = path.find_last_of('/');
    return parse_material_recipe(text, path, slash == std::string::npos ? "." : path.substr(0, slash));
}

}  // namespace npf
