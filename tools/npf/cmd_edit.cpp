// npf edit: edits on a fitted NPF material (paper sec. 4.3; docs/editing.md): NDF transforms,
// diffuse and specular colour swaps, thin-film Fresnel. Steps come from a YAML recipe and from
// flags (recipe first, then the flags in command-line order).
#include "command_line.h"
#include "commands.h"
#include "progress.h"

#include <npf/color/spectrum.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/edit/recipe.h>
#include <npf/shading/npf_texture_file.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = {
    {"-o", true, "output factor texture (.exr); required unless --dry-run"},
    {"--recipe", true, "YAML recipe: a list of steps applied in order (configs/edits/)"},
    {"--matrix", true, "NDF transform by the 3x3 matrix a,b,c,d,e,f,g,h,i (row-major, acts on normals)"},
    {"--stretch-tangent", true, "stretch the NDF (highlight, roughness) along the tangent x by S"},
    {"--stretch-bitangent", true, "stretch the NDF along the bitangent y by S"},
    {"--rotate", true, "rotate the NDF (anisotropy axis) about the normal by DEG, tangent towards bitangent"},
    {"--roughness", true, "scale the roughness by S in every direction (< 1 sharpens, > 1 blurs)"},
    {"--sharpen", true, "sharpen the highlight by F (roughness / F)"},
    {"--blur", true, "blur the highlight by F (roughness x F)"},
    {"--diffuse-from", true, "rho_d of another NPF material (.exr, isotropic or anisotropic)"},
    {"--diffuse-srgb", true, "diffuse albedo R,G,B as sRGB-encoded values in [0, 1] (rho_d = albedo / pi)"},
    {"--diffuse-linear", true, "diffuse albedo R,G,B in linear sRGB"},
    {"--diffuse-spectrum", true, "diffuse albedo spectrum from a .spd file (nm, value)"},
    {"--specular-from", true, "rho_s F of another NPF material; D and G (the highlight's shape) stay"},
    {"--keep-brightness", false, "for --specular-from: scale the new rho_s F to the material's own luminance"},
    {"--thin-film", true, "thin film THICKNESS_NM,FILM_IOR on the material (Airy reflectance)"},
    {"--film-base", true, "for --thin-film: fitted (default; from the material's F), ETA, ETA,K or a metal (Ag, Al, Au, Cr, Cu)"},
    {"--film-mode", true, "for --thin-film: ratio (default; keeps the measured F's shape) or replace"},
    {"--compress-rank", true, "re-compress D and G across wavelengths to ranks D,G (no refit; from a lossless file as convert --rank)"},
    {"--compress-pca", true, "re-compress D and G to the smallest ranks keeping PCA ratios D,G (e.g. 0.99,0.95)"},
    {"--limit-albedo", true, "cap the directional albedo at CAP (in (0, 1], e.g. 1): G is lowered at the views where the material reflects more light than that"},
    {"--phi-cells", true, "azimuth cells of D and G when an isotropic material becomes anisotropic (default 2 x theta)"},
    {"--svd", true, "rank (default: keep the input's SVD ranks) or ratio (the input's kept ratio)"},
    {"--albedo-tolerance", true, "warn when the directional albedo exceeds 1 + this (default 0.005)"},
    {"--no-albedo-check", false, "skip the directional-albedo check after each step"},
    {"--description", true, "the edited material's description"},
    {"--dry-run", false, "apply and report, write nothing"},
    {"--help", false, "show this help"},
};

const std::set<std::string> kStepFlags = {"--matrix", "--stretch-tangent", "--stretch-bitangent", "--rotate",
                                          "--roughness", "--sharpen", "--blur", "--diffuse-from",
                                          "--diffuse-srgb", "--diffuse-linear", "--diffuse-spectrum",
                                          "--specular-from", "--thin-film", "--compress-rank", "--compress-pca",
                                          "--limit-albedo"};

double number(const std::string& flag, const std::string& v) {
    char* end = nullptr;
    const double d = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || !std::isfinite(d)) throw Error(flag, "'" + v + "' is not a number");
    return d;
}

double positive(const std::string& flag, const std::string& v) {
    const double d = number(flag, v);
    if (!(d > 0.0)) throw Error(flag, "must be positive, got '" + v + "'");
    return d;
}

std::vector<double> numbers(const std::string& flag, const std::string& v, std::size_t count) {
    std::vector<double> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = v.find(',', start);
        out.push_back(number(flag, v.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (out.size() != count) {
        throw Error(flag, "expects " + std::to_string(count) + " comma-separated numbers, got '" + v + "'");
    }
    return out;
}

std::string fmt(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}

// Edits work on fitted materials only: any other material (a measurement, a recipe), which
// `npf convert` takes, is refused by name before any work. A file that is missing, not regular,
// too short or an OpenEXR file is left to the NPF reader, whose messages say more.
void require_npf_texture(const std::string& path, const std::string& origin) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return;
    std::ifstream in(path, std::ios::binary);
    unsigned char head[4] = {};
    if (!in.read(reinterpret_cast<char*>(head), sizeof head) || has_exr_magic(head, sizeof head)) return;
    const Error e(path, "not an NPF factor texture; npf edit works on fitted materials (convert it first: npf convert)");
    if (origin.empty()) throw e;
    throw Error(origin, e.what());  // as apply_edits names a step's errors
}

edit::EditStep step_from_flag(const std::string& flag, const std::string& v, const edit::FilmBase& base,
                              edit::FilmMode mode, bool keep_brightness) {
    using edit::EditStep;
    EditStep s;
    if (flag == "--matrix") {
        const std::vector<double> m = numbers(flag, v, 9);
        edit::Mat3 mat;
        for (std::size_t i = 0; i < 9; ++i) mat.m[i] = m[i];
        s = EditStep::ndf(mat, "matrix " + edit::matrix_text(mat));
    } else if (flag == "--stretch-tangent") {
        const double f = positive(flag, v);
        s = EditStep::ndf(edit::stretch_matrix(f, 1.0), "stretch tangent " + fmt(f));
    } else if (flag == "--stretch-bitangent") {
        const double f = positive(flag, v);
        s = EditStep::ndf(edit::stretch_matrix(1.0, f), "stretch bitangent " + fmt(f));
    } else if (flag == "--rotate") {
        const double d = number(flag, v);
        s = EditStep::ndf(edit::rotation_matrix(d), "rotate the anisotropy axis by " + fmt(d) + " degrees");
    } else if (flag == "--roughness" || flag == "--sharpen" || flag == "--blur") {
        const double f = positive(flag, v);
        const double scale = flag == "--sharpen" ? 1.0 / f : f;
        s = EditStep::ndf(edit::roughness_matrix(scale), flag.substr(2) + " " + fmt(f) + " (roughness x " + fmt(scale) + ")");
    } else if (flag == "--diffuse-from") {
        s = EditStep::diffuse_from(v);
    } else if (flag == "--diffuse-srgb" || flag == "--diffuse-linear") {
        const std::vector<double> c = numbers(flag, v, 3);
        color::Rgb rgb{c[0], c[1], c[2]};
        for (double x : rgb) {
            if (x < 0.0) throw Error(flag, "colour components are >= 0, got '" + v + "'");
        }
        if (flag == "--diffuse-srgb") {
            for (double& x : rgb) x = color::srgb_to_linear(x);
        }
        s = EditStep::diffuse_albedo(rgb, std::string("diffuse albedo ") + (flag == "--diffuse-srgb" ? "sRGB" : "linear sRGB") +
                                              " (" + v + ")");
    } else if (flag == "--diffuse-spectrum") {
        s = EditStep::diffuse_albedo(color::read_spd(v), "diffuse albedo from " + v);
    } else if (flag == "--specular-from") {
        s = EditStep::specular_from(v, 1.0, keep_brightness);
    } else if (flag == "--thin-film") {
        const std::vector<double> p = numbers(flag, v, 2);
        if (p[0] < 0.0) throw Error(flag, "the thickness (nm) must not be negative");
        if (!(p[1] > 0.0)) throw Error(flag, "the film index must be positive");
        edit::ThinFilm f;
        f.thickness_nm = p[0];
        f.film_eta = color::SampledSpectrum::constant(p[1]);
        f.base = base;
        f.mode = mode;
        s = EditStep::thin_film(f, "thin film " + fmt(p[0]) + " nm, index " + fmt(p[1]));
    } else if (flag == "--compress-rank" || flag == "--compress-pca") {
        const std::vector<double> p = numbers(flag, v, 2);
        CompressionOptions o;
        if (flag == "--compress-rank") {
            if (!(p[0] >= 1.0 && p[1] >= 1.0 && p[0] == std::floor(p[0]) && p[1] == std::floor(p[1]))) {
                throw Error(flag, "ranks are whole numbers >= 1");
            }
            o.d_rank = int(p[0]);
            o.g_rank = int(p[1]);
        } else {
            if (!(p[0] > 0.0 && p[0] <= 1.0 && p[1] > 0.0 && p[1] <= 1.0)) throw Error(flag, "ratios are in (0, 1]");
            o.d_ratio = p[0];
            o.g_ratio = p[1];
        }
        s = EditStep::compress(o, std::string("compress D, G to ") + (flag == "--compress-rank" ? "ranks " : "PCA ratios ") + v);
    } else if (flag == "--limit-albedo") {
        const double cap = number(flag, v);
        if (!(cap > 0.0 && cap <= 1.0)) throw Error(flag, "the cap must be in (0, 1], got '" + v + "'");
        s = EditStep::limit_albedo(cap);
    }
    s.origin = flag;
    return s;
}

}  // namespace

int run_edit(const std::vector<std::string>& args) {
    CommandLine cl("edit", args, kFlags);
    const bool dry = cl.has("--dry-run");
    if (cl.has("--help")) {
        std::printf("usage: npf edit IN.exr -o OUT.exr [--recipe FILE.yaml] [edit flags]\n\n"
                    "Edits a fitted NPF material (paper sec. 4.3): NDF linear transforms and their friendly forms,\n"
                    "diffuse colour, specular colour, thin-film Fresnel. The recipe's steps run first, then the edit\n"
                    "flags in the order given; each step's record goes into the file's metadata (edit_001, ...), which\n"
                    "npf info shows. After each step the directional albedo is checked (a warning above 1).\n"
                    "Conventions, maths and limits: docs/editing.md; example recipes: configs/edits/. Examples:\n"
                    "  npf edit copper.exr -o copper_wide.exr --stretch-tangent 2 --rotate 30\n"
                    "  npf edit felt.exr -o felt_red.exr --diffuse-srgb 0.8,0.1,0.1\n"
                    "  npf edit steel.exr -o steel_film.exr --thin-film 615,1.3 --film-base fitted\n"
                    "  npf edit paper.exr -o paper_capped.exr --limit-albedo 1\n\n%s",
                    usage_lines(kFlags).c_str());
        return 0;
    }
    cl.expect_positional(1, 1, "one IN.exr");
    if (!dry) cl.require("-o");
    const std::string input = cl.positional()[0], output = cl.value("-o");

    // Everything that can fail on the command line fails before any work.
    edit::EditRecipe recipe;
    if (cl.has("--recipe")) recipe = edit::load_edit_recipe(cl.value("--recipe"));
    edit::EditOptions options = recipe.options;
    const edit::FilmBase base = edit::parse_film_base(cl.value("--film-base", "fitted"), "--film-base");
    edit::FilmMode mode = edit::FilmMode::Ratio;
    if (cl.has("--film-mode")) {
        const std::string v = cl.value("--film-mode");
        if (v == "replace") mode = edit::FilmMode::Replace;
        else if (v != "ratio") throw Error("--film-mode", "'" + v + "' is not ratio or replace");
    }
    if ((cl.has("--film-base") || cl.has("--film-mode")) && !cl.has("--thin-film")) {
        throw Error(cl.has("--film-base") ? "--film-base" : "--film-mode", "applies to --thin-film, which is not given");
    }
    std::vector<edit::EditStep> steps = recipe.steps;
    if (cl.has("--keep-brightness") && !cl.has("--specular-from")) {
        throw Error("--keep-brightness", "applies to --specular-from, which is not given");
    }
    for (const auto& [flag, value] : cl.flags_in_order()) {
        if (kStepFlags.count(flag)) steps.push_back(step_from_flag(flag, value, base, mode, cl.has("--keep-brightness")));
    }
    if (cl.has("--phi-cells")) {
        const double v = number("--phi-cells", cl.value("--phi-cells"));
        if (v != std::floor(v) || v < 0 || v > 4096) throw Error("--phi-cells", "expects a whole number in [0, 4096]");
        options.ndf.phi_cells = int(v);
    }
    if (cl.has("--svd")) {
        const std::string v = cl.value("--svd");
        if (v == "rank") options.ndf.recompress = edit::Recompress::KeepRank;
        else if (v == "ratio") options.ndf.recompress = edit::Recompress::KeptRatio;
        else throw Error("--svd", "'" + v + "' is not rank or ratio");
    }
    if (cl.has("--albedo-tolerance")) {
        options.albedo_tolerance = number("--albedo-tolerance", cl.value("--albedo-tolerance"));
        if (options.albedo_tolerance < 0.0) throw Error("--albedo-tolerance", "must not be negative");
    }
    if (cl.has("--no-albedo-check")) options.check_albedo = false;
    if (cl.has("--description")) options.description = cl.value("--description");
    if (steps.empty() && !cl.has("--recipe")) {
        throw Error("edit", "no edits given (flags or --recipe; configs/edits/identity.yaml is the identity)");
    }

    require_npf_texture(input, "");
    for (const edit::EditStep& s : steps) {
        if (s.kind == edit::EditStep::Kind::DiffuseMaterial || s.kind == edit::EditStep::Kind::SpecularMaterial)
            require_npf_texture(s.path, s.origin);
    }
    if (!dry) check_output_path(output);  // a destination that cannot be written fails now, not after the edits
    const NpfModel model = read_npf_texture(input);
    std::printf("%s: %s, %zu %s, D %d x %d, G %d x %d; %zu step%s\n", input.c_str(), model.isotropic() ? "isotropic" : "anisotropic",
                model.channel_count(), model.channels.is_rgb() ? "RGB channels" : "wavelengths", model.d_theta, model.d_phi,
                model.g_theta, model.g_phi, steps.size(), steps.size() == 1 ? "" : "s");
    std::fflush(stdout);
    // Only a long step reports progress (limit_albedo on a large anisotropic material): one bar
    // per step, on a terminal.
    std::unique_ptr<ProgressBar> bar;
    std::size_t step_index = 0;
    options.progress = [&](double f) {
        if (!bar) bar = std::make_unique<ProgressBar>("  [" + std::to_string(step_index + 1) + "] " + steps[step_index].label, true);
        bar->update(f);
    };
    const edit::EditResult result = edit::apply_edits(model, steps, options, [&](std::size_t i, const edit::EditRecord& r) {
        if (bar) bar->finish();
        bar.reset();
        step_index = i + 1;
        std::printf("  [%zu] %s\n      %s\n", i + 1, steps[i].label.c_str(), r.summary.c_str());
        std::fflush(stdout);
        for (const std::string& w : r.warnings) std::fprintf(stderr, "npf edit: warning: step %zu: %s\n", i + 1, w.c_str());
    });
    if (options.check_albedo) {
        std::printf("  directional albedo: largest %.4f (input %.4f)\n", result.output_albedo.max, result.input_albedo.max);
    }
    if (dry) {
        std::printf("dry run: nothing written\n");
        return 0;
    }
    write_npf_texture(result.model, output);
    if (result.history_keys.empty()) {
        std::printf("wrote %s (no steps)\n", output.c_str());
    } else {
        std::printf("wrote %s (history: %s to %s)\n", output.c_str(), result.history_keys.front().c_str(),
                    result.history_keys.back().c_str());
    }
    return 0;
}

}  // namespace npf::cli
