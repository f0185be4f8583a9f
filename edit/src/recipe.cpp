#include <npf/edit/recipe.h>
#include <npf/edit/compression.h>

#include <npf/edit/colour_edits.h>
#include <npf/shading/npf_texture_file.h>

#include "tables.h"

#include <npf/converter/data_files.h>
#include <npf/core/error.h>
#include <npf/core/input_file.h>

#include <npf/converter/yaml_context.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace npf::edit {

namespace {

// Errors name the recipe, the line and the key: "recipe.yaml:7: key 'stretch': ...".
using Context = YamlContext;

// number | [[nm, value], ...] | path of a .spd file
color::SampledSpectrum parse_spectrum(const Context& cx, const YAML::Node& node, const std::string& key) {
    if (node.IsScalar()) {
        std::istringstream is(node.Scalar());
        double v = 0.0;
        if (is >> v && is.eof()) return color::SampledSpectrum::constant(cx.number(node, key));
        const std::string p = cx.path(node, key);
        return cx.at(node, key, [&] { return color::read_spd(p); });
    }
    if (!node.IsSequence() || node.size() == 0) cx.fail(node, key, "expected a number, a .spd file or [[wavelength_nm, value], ...]");
    std::vector<double> wl, v;
    for (const YAML::Node& row : node) {
        if (!row.IsSequence() || row.size() != 2) cx.fail(row, key, "each row is [wavelength_nm, value]");
        wl.push_back(cx.number(row[0], key));
        v.push_back(cx.number(row[1], key));
    }
    return cx.at(node, key, [&] { return color::SampledSpectrum(wl, v); });
}

color::Rgb parse_rgb(const Context& cx, const YAML::Node& node, const std::string& key) {
    if (!node.IsSequence() || node.size() != 3) cx.fail(node, key, "expected [r, g, b]");
    color::Rgb c{};
    for (std::size_t i = 0; i < 3; ++i) {
        c[i] = cx.number(node[i], key);
        if (c[i] < 0.0) cx.fail(node[i], key, "colour components are >= 0");
    }
    return c;
}

Mat3 parse_matrix(const Context& cx, const YAML::Node& node) {
    Mat3 m;
    const char* key = "matrix";
    if (!node.IsSequence()) cx.fail(node, key, "expected [[a, b, c], [d, e, f], [g, h, i]]");
    if (node.size() == 9) {
        for (std::size_t i = 0; i < 9; ++i) m.m[i] = cx.number(node[i], key);
        return m;
    }
    if (node.size() != 3) cx.fail(node, key, "expected three rows of three numbers (or nine numbers)");
    for (std::size_t i = 0; i < 3; ++i) {
        if (!node[i].IsSequence() || node[i].size() != 3) cx.fail(node[i], key, "each row holds three numbers");
        for (std::size_t j = 0; j < 3; ++j) m(int(i), int(j)) = cx.number(node[i][j], key);
    }
    return m;
}

// A number, or a mapping with the one key `inner`.
double scalar_or(const Context& cx, const YAML::Node& node, const std::string& key, const char* inner) {
    if (node.IsScalar()) return cx.number(node, key);
    cx.only(node, key, {inner});
    if (!node[inner]) cx.fail(node, key, std::string("missing '") + inner + "'");
    return cx.number(node[inner], inner);
}

FilmBase parse_base(const Context& cx, const YAML::Node& node) {
    if (node.IsScalar()) return cx.at(node, "base", [&] { return parse_film_base(node.Scalar(), "base"); });
    cx.only(node, "base", {"eta", "k"});
    if (!node["eta"]) cx.fail(node, "base", "missing 'eta'");
    FilmBase b;
    b.fitted = false;
    b.eta = parse_spectrum(cx, node["eta"], "eta");
    if (node["k"]) b.k = parse_spectrum(cx, node["k"], "k");
    b.label = "given index";
    return b;
}

EditStep parse_step(const Context& cx, const YAML::Node& node) {
    if (!node.IsMap() || node.size() != 1) {
        cx.fail(node, "steps", "each step is a mapping with one key: matrix, stretch, rotate, roughness, sharpen, blur, "
                               "diffuse, specular, thin_film, compress or limit_albedo");
    }
    const auto kv = *node.begin();
    const std::string kind = kv.first.Scalar();
    const YAML::Node v = kv.second;
    if (v.IsNull()) cx.fail(kv.first, kind, "has no value");
    EditStep s;
    if (kind == "matrix") {
        const Mat3 m = parse_matrix(cx, v);
        s = EditStep::ndf(m, "matrix " + matrix_text(m));
    } else if (kind == "stretch") {
        cx.only(v, kind, {"tangent", "bitangent"});
        if (!v["tangent"] && !v["bitangent"]) cx.fail(v, kind, "give tangent, bitangent or both");
        const double t = v["tangent"] ? cx.positive(v["tangent"], "tangent") : 1.0;
        const double b = v["bitangent"] ? cx.positive(v["bitangent"], "bitangent") : 1.0;
        s = EditStep::ndf(stretch_matrix(t, b), "stretch tangent " + detail::num(t) + ", bitangent " + detail::num(b));
    } else if (kind == "rotate") {
        const double deg = scalar_or(cx, v, kind, "degrees");
        s = EditStep::ndf(rotation_matrix(deg), "rotate the anisotropy axis by " + detail::num(deg) + " degrees");
    } else if (kind == "roughness" || kind == "sharpen" || kind == "blur") {
        const double f = kind == "roughness" ? scalar_or(cx, v, kind, "scale") : scalar_or(cx, v, kind, "factor");
        if (!(f > 0.0)) cx.fail(v, kind, "must be positive, got " + detail::num(f));
        const double scale = kind == "sharpen" ? 1.0 / f : f;
        s = EditStep::ndf(roughness_matrix(scale), kind + " " + detail::num(f) + " (roughness x " + detail::num(scale) + ")");
    } else if (kind == "diffuse") {
        cx.only(v, kind, {"from", "srgb", "linear_srgb", "spectrum", "scale"});
        int sources = 0;
        for (const char* k : {"from", "srgb", "linear_srgb", "spectrum"}) sources += v[k] ? 1 : 0;
        if (sources != 1) cx.fail(v, kind, "give exactly one of from, srgb, linear_srgb, spectrum");
        double scale = 1.0;
        if (v["scale"]) {
            scale = cx.number(v["scale"], "scale");
            if (scale < 0.0) cx.fail(v["scale"], "scale", "must not be negative");
        }
        if (v["from"]) {
            s = EditStep::diffuse_from(cx.path(v["from"], "from"), scale);
        } else if (v["spectrum"]) {
            color::SampledSpectrum a = parse_spectrum(cx, v["spectrum"], "spectrum");
            for (double x : a.values()) {
                if (x < 0.0) cx.fail(v["spectrum"], "spectrum", "albedo values are >= 0");
            }
            if (scale != 1.0) {
                std::vector<double> vals = a.values();
                for (double& x : vals) x *= scale;
                a = color::SampledSpectrum(a.wavelengths(), vals);
            }
            s = EditStep::diffuse_albedo(a, "diffuse albedo from a spectrum" + (scale != 1.0 ? " x " + detail::num(scale) : ""));
        } else {
            const bool encoded = bool(v["srgb"]);
            const color::Rgb c = parse_rgb(cx, encoded ? v["srgb"] : v["linear_srgb"], encoded ? "srgb" : "linear_srgb");
            color::Rgb lin = c;
            if (encoded) {
                for (double& x : lin) x = color::srgb_to_linear(x);
            }
            for (double& x : lin) x *= scale;
            s = EditStep::diffuse_albedo(lin, std::string("diffuse albedo ") + (encoded ? "sRGB" : "linear sRGB") + " (" +
                                                  detail::num(c[0], 4) + ", " + detail::num(c[1], 4) + ", " +
                                                  detail::num(c[2], 4) + ")" +
                                                  (scale != 1.0 ? " x " + detail::num(scale) : ""));
        }
    } else if (kind == "specular") {
        cx.only(v, kind, {"from", "scale", "keep_brightness"});
        if (!v["from"]) cx.fail(v, kind, "missing 'from'");
        double scale = 1.0;
        if (v["scale"]) {
            scale = cx.number(v["scale"], "scale");
            if (scale < 0.0) cx.fail(v["scale"], "scale", "must not be negative");
        }
        bool keep = false;
        if (v["keep_brightness"]) {
            const std::string b = cx.text(v["keep_brightness"], "keep_brightness");
            if (b == "true" || b == "yes") keep = true;
            else if (b != "false" && b != "no") cx.fail(v["keep_brightness"], "keep_brightness", "expected true or false");
        }
        s = EditStep::specular_from(cx.path(v["from"], "from"), scale, keep);
    } else if (kind == "thin_film") {
        cx.only(v, kind, {"thickness", "film_ior", "base", "mode"});
        if (!v["thickness"]) cx.fail(v, kind, "missing 'thickness' (nm)");
        if (!v["film_ior"]) cx.fail(v, kind, "missing 'film_ior'");
        ThinFilm f;
        f.thickness_nm = cx.number(v["thickness"], "thickness");
        if (f.thickness_nm < 0.0) cx.fail(v["thickness"], "thickness", "must not be negative (nm)");
        f.film_eta = parse_spectrum(cx, v["film_ior"], "film_ior");
        for (double x : f.film_eta.values()) {
            if (!(x > 0.0)) cx.fail(v["film_ior"], "film_ior", "indices are positive");
        }
        if (v["base"]) f.base = parse_base(cx, v["base"]);
        if (v["mode"]) {
            const std::string mode = cx.text(v["mode"], "mode");
            if (mode == "ratio") f.mode = FilmMode::Ratio;
            else if (mode == "replace") f.mode = FilmMode::Replace;
            else cx.fail(v["mode"], "mode", "'" + mode + "' is not ratio or replace");
        }
        const std::string label = "thin film " + detail::num(f.thickness_nm) + " nm, index " +
                                  (v["film_ior"].IsScalar() ? v["film_ior"].Scalar() : std::string("(spectrum)"));
        s = EditStep::thin_film(f, label);
    } else if (kind == "compress") {
        cx.only(v, kind, {"rank", "pca"});
        if (bool(v["rank"]) == bool(v["pca"])) cx.fail(v, kind, "give exactly one of rank: [D, G] or pca: [D, G]");
        const bool by_rank = bool(v["rank"]);
        const YAML::Node pair = by_rank ? v["rank"] : v["pca"];
        const char* key = by_rank ? "rank" : "pca";
        if (!pair.IsSequence() || pair.size() != 2) cx.fail(pair, key, "expected two values: [D, G]");
        const double a = cx.number(pair[0], key), b = cx.number(pair[1], key);
        CompressionOptions o;
        if (by_rank) {
            if (!(a >= 1.0 && b >= 1.0 && a == std::floor(a) && b == std::floor(b))) cx.fail(pair, key, "ranks are whole numbers >= 1");
            o.d_rank = int(a);
            o.g_rank = int(b);
        } else {
            if (!(a > 0.0 && a <= 1.0 && b > 0.0 && b <= 1.0)) cx.fail(pair, key, "ratios are in (0, 1]");
            o.d_ratio = a;
            o.g_ratio = b;
        }
        s = EditStep::compress(o, std::string("compress D, G ") + (by_rank ? "to ranks " : "to PCA ratios ") +
                                      detail::num(a) + ", " + detail::num(b));
    } else if (kind == "limit_albedo") {
        const double cap = scalar_or(cx, v, kind, "cap");
        if (!(cap > 0.0 && cap <= 1.0)) cx.fail(v, kind, "the cap must be in (0, 1], got " + detail::num(cap));
        s = EditStep::limit_albedo(cap);
    } else {
        cx.fail(kv.first, kind,
                "unknown step (expected one of: matrix, stretch, rotate, roughness, sharpen, blur, diffuse, specular, "
                "thin_film, compress, limit_albedo)");
    }
    s.origin = cx.where(kv.first);
    return s;
}

std::string read_whole(const std::string& path) {
    require_regular_file(path, "an edit recipe (.yaml)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, "cannot open");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

bool is_history_key(const std::string& key, int* number) {
    if (key.size() < 6 || key.compare(0, 5, "edit_") != 0) return false;
    int n = 0;
    for (std::size_t i = 5; i < key.size(); ++i) {
        if (key[i] < '0' || key[i] > '9' || n > 100000000) return false;
        n = n * 10 + (key[i] - '0');
    }
    if (number) *number = n;
    return true;
}

// The factors (not the metadata) of two models are the same, bit for bit.
bool same_factors(const NpfModel& a, const NpfModel& b) {
    return a.d_theta == b.d_theta && a.d_phi == b.d_phi && a.g_theta == b.g_theta && a.g_phi == b.g_phi &&
           a.f_theta == b.f_theta && a.rho_d == b.rho_d && a.rho_s == b.rho_s && a.F == b.F && a.D.basis == b.D.basis &&
           a.D.weights == b.D.weights && a.G.basis == b.G.basis && a.G.weights == b.G.weights;
}

std::string history_key(int n) {
    char b[32];
    std::snprintf(b, sizeof b, "edit_%03d", n);
    return b;
}

}  // namespace

EditStep EditStep::ndf(const Mat3& m, std::string label) {
    EditStep s;
    s.kind = Kind::Ndf;
    s.matrix = m;
    s.label = std::move(label);
    return s;
}

EditStep EditStep::diffuse_from(std::string path, double scale) {
    EditStep s;
    s.kind = Kind::DiffuseMaterial;
    s.label = "diffuse from " + path + (scale != 1.0 ? " x " + detail::num(scale) : "");
    s.path = std::move(path);
    s.scale = scale;
    return s;
}

EditStep EditStep::diffuse_albedo(color::SampledSpectrum albedo, std::string label) {
    EditStep s;
    s.kind = Kind::DiffuseSpectrum;
    s.spectrum = std::move(albedo);
    s.label = std::move(label);
    return s;
}

EditStep EditStep::diffuse_albedo(const color::Rgb& linear, std::string label) {
    EditStep s;
    s.kind = Kind::DiffuseRgb;
    s.rgb = linear;
    s.label = std::move(label);
    return s;
}

EditStep EditStep::specular_from(std::string path, double scale, bool keep_brightness) {
    EditStep s;
    s.kind = Kind::SpecularMaterial;
    s.label = "specular from " + path + (scale != 1.0 ? " x " + detail::num(scale) : "") +
              (keep_brightness ? ", brightness kept" : "");
    s.path = std::move(path);
    s.scale = scale;
    s.keep_brightness = keep_brightness;
    return s;
}

EditStep EditStep::thin_film(ThinFilm film, std::string label) {
    EditStep s;
    s.kind = Kind::ThinFilm;
    s.film = std::move(film);
    s.label = std::move(label);
    return s;
}

EditStep EditStep::compress(const CompressionOptions& options, std::string label) {
    EditStep s;
    s.kind = Kind::Compress;
    s.compression = options;
    s.label = std::move(label);
    return s;
}

EditStep EditStep::limit_albedo(double cap) {
    EditStep s;
    s.kind = Kind::LimitAlbedo;
    s.cap = cap;
    s.label = "limit the directional albedo to " + detail::num(cap);
    return s;
}

FilmBase parse_film_base(const std::string& text, const std::string& what) {
    FilmBase b;
    if (text == "fitted" || text.empty()) return b;
    b.fitted = false;
    // "eta" or "eta,k"
    std::vector<double> parts;
    std::stringstream ss(text);
    bool numbers = true;
    for (std::string p; std::getline(ss, p, ',');) {
        char* end = nullptr;
        const double v = std::strtod(p.c_str(), &end);
        if (p.empty() || end != p.c_str() + p.size() || !std::isfinite(v)) {
            numbers = false;
            break;
        }
        parts.push_back(v);
    }
    if (numbers && (parts.size() == 1 || parts.size() == 2)) {
        if (!(parts[0] > 0.0) || (parts.size() == 2 && parts[1] < 0.0)) {
            throw Error(what, "'" + text + "': eta must be positive and k >= 0");
        }
        b.eta = color::SampledSpectrum::constant(parts[0]);
        b.k = color::SampledSpectrum::constant(parts.size() == 2 ? parts[1] : 0.0);
        b.label = parts.size() == 2 ? "eta " + detail::num(parts[0]) + " + " + detail::num(parts[1]) + "i" : "dielectric " + detail::num(parts[0]);
        return b;
    }
    if (numbers) throw Error(what, "'" + text + "' is neither fitted, eta, eta,k nor a metal name");
    const std::string eta = find_data_file("ior/" + text + ".eta.spd"), k = find_data_file("ior/" + text + ".k.spd");
    if (eta.empty() || k.empty()) {
        throw Error(what, "'" + text + "' is neither fitted, a number, eta,k nor a metal of the shipped tables (Ag, Al, Au, Cr, Cu)");
    }
    b.eta = color::read_spd(eta);
    b.k = color::read_spd(k);
    b.label = text;
    return b;
}

EditRecipe parse_edit_recipe(const std::string& yaml, const std::string& source, const std::string& base_dir) {
    Context cx;
    cx.source = source;
    cx.base_dir = base_dir;
    YAML::Node root;
    try {
        root = YAML::Load(yaml);
    } catch (const YAML::ParserException& e) {
        throw Error(source + ":" + std::to_string(e.mark.line + 1), "not valid YAML: " + e.msg);
    }
    if (!root.IsMap()) throw Error(source, "an edit recipe is a YAML mapping with a list of steps (see configs/edits/)");
    cx.only(root, "", {"description", "steps", "options"});
    EditRecipe r;
    if (root["description"]) {
        r.options.description = cx.text(root["description"], "description");
        r.has_description = true;
    }
    if (!root["steps"]) throw Error(source, "missing 'steps' (a list; [] for none)");
    const YAML::Node steps = root["steps"];
    if (!steps.IsSequence()) cx.fail(steps, "steps", "expected a list of steps");
    for (const YAML::Node& s : steps) r.steps.push_back(parse_step(cx, s));
    if (root["options"]) {
        const YAML::Node o = root["options"];
        cx.only(o, "options", {"phi_cells", "svd", "albedo_tolerance"});
        if (o["phi_cells"]) {
            const double v = cx.number(o["phi_cells"], "phi_cells");
            if (v != std::floor(v) || v < 0 || v > 4096) cx.fail(o["phi_cells"], "phi_cells", "expected a whole number in [0, 4096]");
            r.options.ndf.phi_cells = int(v);
            r.has_phi_cells = true;
        }
        if (o["svd"]) {
            const std::string v = cx.text(o["svd"], "svd");
            if (v == "rank") r.options.ndf.recompress = Recompress::KeepRank;
            else if (v == "ratio") r.options.ndf.recompress = Recompress::KeptRatio;
            else cx.fail(o["svd"], "svd", "'" + v + "' is not rank or ratio");
            r.has_svd = true;
        }
        if (o["albedo_tolerance"]) {
            r.options.albedo_tolerance = cx.number(o["albedo_tolerance"], "albedo_tolerance");
            if (r.options.albedo_tolerance < 0.0) cx.fail(o["albedo_tolerance"], "albedo_tolerance", "must not be negative");
            r.has_albedo_tolerance = true;
        }
    }
    return r;
}

EditRecipe load_edit_recipe(const std::string& path) {
    const std::string text = read_whole(path);
    std::string dir = std::filesystem::path(path).parent_path().string();
    if (dir.empty()) dir = ".";
    return parse_edit_recipe(text, path, dir);
}

std::vector<std::pair<std::string, std::string>> edit_history(const NpfModel& model) {
    std::vector<std::pair<int, std::pair<std::string, std::string>>> found;
    for (const auto& kv : model.metadata) {
        int n = 0;
        if (is_history_key(kv.first, &n)) found.push_back({n, kv});
    }
    std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::pair<std::string, std::string>> out;
    for (auto& f : found) out.push_back(std::move(f.second));
    return out;
}

EditResult apply_edits(const NpfModel& model, const std::vector<EditStep>& steps, const EditOptions& options,
                       const std::function<void(std::size_t, const EditRecord&)>& on_step) {
    EditResult r;
    r.model = model;
    int next = 1;
    for (const auto& kv : model.metadata) {
        int n = 0;
        if (is_history_key(kv.first, &n)) next = std::max(next, n + 1);
    }
    if (options.check_albedo) r.input_albedo = r.output_albedo = albedo_report(model, options.albedo);
    const double limit = 1.0 + options.albedo_tolerance;
    for (std::size_t i = 0; i < steps.size(); ++i) {
        const EditStep& s = steps[i];
        EditRecord rec;
        const NpfModel before = r.model;
        try {
            switch (s.kind) {
            case EditStep::Kind::Ndf:
                r.model = transform_ndf(r.model, s.matrix, options.ndf, &rec);
                break;
            case EditStep::Kind::DiffuseMaterial:
                r.model = replace_diffuse(r.model, read_npf_texture(s.path), s.scale, &rec);
                break;
            case EditStep::Kind::DiffuseSpectrum:
                r.model = replace_diffuse_albedo(r.model, s.spectrum, &rec);
                break;
            case EditStep::Kind::DiffuseRgb:
                r.model = replace_diffuse_albedo(r.model, s.rgb, &rec);
                break;
            case EditStep::Kind::SpecularMaterial:
                r.model = replace_specular(r.model, read_npf_texture(s.path), SpecularSwap{s.scale, s.keep_brightness}, &rec);
                break;
            case EditStep::Kind::ThinFilm:
                r.model = apply_thin_film(r.model, s.film, &rec);
                break;
            case EditStep::Kind::Compress:
                r.model = compress_model(r.model, s.compression, &rec);
                break;
            case EditStep::Kind::LimitAlbedo: {
                AlbedoLimit cap;
                cap.cap = s.cap;
                cap.threads = options.albedo.threads;
                cap.progress = options.progress;
                r.model = limit_albedo(r.model, cap, &rec);
                break;
            }
            }
        } catch (const Error& e) {
            if (s.origin.empty()) throw;
            throw Error(s.origin, e.what());
        }
        if (options.check_albedo) {
            // An edit that changed nothing (an identity) keeps the last measurement.
            const AlbedoReport a = same_factors(before, r.model) ? r.output_albedo : albedo_report(r.model, options.albedo);
            const std::string where = "theta_i " + detail::num(a.theta_deg, 3) + " deg, phi_i " + detail::num(a.phi_deg, 3) +
                                      " deg, channel " + std::to_string(a.channel);
            rec.summary += "; largest directional albedo " + detail::num(a.max, 4) + " (" + where + ")";
            if (a.max > limit) {
                std::string w = "the directional albedo reaches " + detail::num(a.max, 4) + " (" + where +
                                "): the material reflects more light than it receives";
                if (r.input_albedo.max > limit) w += " (the input already reached " + detail::num(r.input_albedo.max, 4) + ")";
                rec.warnings.push_back(w);
            }
            r.output_albedo = a;
        }
        std::string value = s.label + ": " + rec.summary;
        for (const std::string& w : rec.warnings) value += "; WARNING: " + w;
        const std::string key = history_key(next++);
        r.model.metadata.emplace_back(key, value);
        r.history_keys.push_back(key);
        r.records.push_back(rec);
        if (on_step) on_step(i, rec);
    }
    if (!options.description.empty()) {
        bool found = false;
        for (auto& kv : r.model.metadata) {
            if (kv.first == "description") kv.second = options.description, found = true;
        }
        if (!found) r.model.metadata.emplace_back("description", options.description);
    }
    return r;
}

}  // namespace npf::edit
