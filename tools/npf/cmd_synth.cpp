// npf synth: makes an RGL `.bsdf` file from an analytic material, given as a YAML recipe
// (configs/materials/) or by flags ("virtual acquisition").
#include "command_line.h"

#include <npf/core/number_text.h>
#include "commands.h"
#include "file_uses.h"
#include "progress.h"

#include <npf/materials/data_files.h>
#include <npf/materials/material_recipe.h>
#include <npf/materials/open_material.h>
#include <npf/materials/rgl_writer.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = flag_table({
    "-o VALUE  output .bsdf file (required unless the recipe names one)",
    "--recipe VALUE  YAML material recipe (see docs/synth.md, configs/materials/)",
    "--name VALUE  material name, written as the file's description",
    "--distribution VALUE  ggx (default) or beckmann",
    "--alpha VALUE  roughness: A or AX,AY (tangent, bitangent)",
    "--rotation VALUE  rotation of the lobe's tangent about the normal, degrees",
    "--conductor VALUE  metal Fresnel from the shipped tables: Ag, Al, Au, Cr, Cu",
    "--dielectric VALUE  dielectric Fresnel with this index (e.g. 1.5)",
    "--schlick VALUE  Schlick Fresnel with this F0: a number or r,g,b (sRGB)",
    "--thin-film VALUE  thin film: THICKNESS_NM,FILM_IOR,BASE (BASE a metal name or an index)",
    "--diffuse VALUE  Lambertian albedo: a number, r,g,b (sRGB) or an .spd file",
    "--wavelengths VALUE  rgb, or start:end:count or a,b,c in nm (default 360:1000:195)",
    "--anisotropy VALUE  auto (default), isotropic or anisotropic",
    "--phi VALUE  anisotropic phi_i nodes over [-pi, pi] (default 24)",
    "--theta VALUE  theta_i nodes (default 8)",
    "--ndf VALUE  ndf/sigma columns (default 128)",
    "--ndf-rows VALUE  anisotropic ndf/sigma rows (default 64)",
    "--vndf VALUE  vndf grid size (default 128)",
    "--data VALUE  data grid size (default 32)",
    "--threads VALUE  threads (default: all cores)",
    "--quiet  no progress bar",
});

const char* kHelp =
    "usage: npf synth -o OUT.bsdf [--recipe FILE.yaml] [material flags] [grid flags]\n\n"
    "Writes an RGL .bsdf file (readable by every RGL reader) from an analytic material.\n"
    "Flags override the recipe. Example, an anisotropic spectral copper with a faint\n"
    "diffuse term:\n"
    "  npf synth -o copper.bsdf --conductor Cu --alpha 0.08,0.35 --diffuse 0.02\n\n";

// A Fresnel factory's refusal of an out-of-range value, reported against the flag.
template <class Make>
Fresnel for_flag(const char* flag, Make make) {
    try {
        return make();
    } catch (const Error& e) {
        throw Error(flag, e.problem());
    }
}

// --thin-film THICKNESS_NM,FILM_IOR,BASE with BASE an index or a shipped metal's name.
Fresnel thin_film_fresnel(const std::string& t) {
    const auto a = t.find(','), b = a == std::string::npos ? a : t.find(',', a + 1);
    if (b == std::string::npos) throw Error("--thin-film", "needs THICKNESS_NM,FILM_IOR,BASE");
    const double thickness = parse_finite_number(t.substr(0, a), "--thin-film");
    const double film = parse_finite_number(t.substr(a + 1, b - a - 1), "--thin-film");
    const std::string base = t.substr(b + 1);
    const std::optional<double> base_ior = finite_number_of(base);
    if (!(thickness >= 0.0)) throw Error("--thin-film", "the film thickness must not be negative (nm)");
    if (base_ior) {
        return for_flag("--thin-film", [&] {
            return Fresnel::thin_film(thickness, color::SampledSpectrum::constant(film),
                                      color::SampledSpectrum::constant(*base_ior), color::SampledSpectrum::constant(0.0));
        });
    }
    const std::string eta = find_data_file("ior/" + base + ".eta.spd"), k = find_data_file("ior/" + base + ".k.spd");
    if (eta.empty() || k.empty()) throw Error("--thin-film", "no refractive index tables for metal '" + base + "'");
    return for_flag("--thin-film", [&] {
        return Fresnel::thin_film(thickness, color::SampledSpectrum::constant(film), color::read_spd(eta), color::read_spd(k));
    });
}

// The lobe flags: a lobe is created when any is given and the recipe has none, else they edit the
// recipe's first lobe.
void apply_lobe_flags(const CommandLine& cl, AnalyticMaterial& material) {
    const bool lobe_flags = cl.has("--alpha") || cl.has("--distribution") || cl.has("--rotation") ||
                            cl.has("--conductor") || cl.has("--dielectric") || cl.has("--schlick") ||
                            cl.has("--thin-film");
    if (lobe_flags && material.specular.empty()) material.specular.emplace_back();
    const int fresnel_flags = int(cl.has("--conductor")) + int(cl.has("--dielectric")) + int(cl.has("--schlick")) +
                              int(cl.has("--thin-film"));
    if (fresnel_flags > 1) throw Error("--conductor/--dielectric/--schlick/--thin-film", "give at most one Fresnel term");
    if (!lobe_flags) return;
    SpecularLobe& lobe = material.specular.front();
    lobe.ndf.type = cl.choice<MicrofacetDistribution>(
        "--distribution", {{"ggx", MicrofacetDistribution::Ggx}, {"beckmann", MicrofacetDistribution::Beckmann}},
        lobe.ndf.type, "is not ggx or beckmann");
    if (cl.has("--alpha")) {
        const std::string a = cl.value("--alpha");
        const auto comma = a.find(',');
        lobe.ndf.alpha_x = float(parse_finite_number(a.substr(0, comma), "--alpha"));
        lobe.ndf.alpha_y = comma == std::string::npos ? lobe.ndf.alpha_x : float(parse_finite_number(a.substr(comma + 1), "--alpha"));
        if (!(lobe.ndf.alpha_x >= 1e-4f && lobe.ndf.alpha_y >= 1e-4f && lobe.ndf.alpha_x <= 4.f && lobe.ndf.alpha_y <= 4.f)) {
            throw Error("--alpha", "roughness must lie in [1e-4, 4]");
        }
    }
    if (cl.has("--rotation")) lobe.ndf.rotation = float(parse_finite_number(cl.value("--rotation"), "--rotation") * kPiD / 180.0);
    if (cl.has("--conductor")) lobe.fresnel = conductor_fresnel(cl.value("--conductor"), "--conductor");
    if (cl.has("--dielectric")) {
        const double eta = parse_finite_number(cl.value("--dielectric"), "--dielectric");
        lobe.fresnel = for_flag("--dielectric", [&] { return Fresnel::dielectric(color::SampledSpectrum::constant(eta)); });
    }
    if (cl.has("--schlick")) {
        const color::SampledSpectrum f0 = spectrum_from_text(cl.value("--schlick"), "--schlick");
        lobe.fresnel = for_flag("--schlick", [&] { return Fresnel::schlick(f0); });
    }
    if (cl.has("--thin-film")) lobe.fresnel = thin_film_fresnel(cl.value("--thin-film"));
}

// The rest of the material and the file's channels and grids.
void apply_writer_flags(const CommandLine& cl, MaterialRecipe& recipe) {
    if (cl.has("--diffuse")) recipe.material.diffuse = spectrum_from_text(cl.value("--diffuse"), "--diffuse");
    if (cl.has("--name")) recipe.material.name = recipe.writer.description = cl.value("--name");
    if (cl.has("--wavelengths")) recipe.writer.channels = parse_channel_list(cl.value("--wavelengths"), "--wavelengths");
    if (!recipe.writer.channels.is_rgb() && recipe.writer.channels.wavelengths().empty()) {
        recipe.writer.channels = Channels::spectral(parse_wavelength_list(kDefaultWavelengths, "default wavelengths"));
    }
    if (!recipe.writer.channels.is_rgb()) recipe.material.wavelengths = recipe.writer.channels.wavelengths();
    recipe.writer.anisotropy = cl.choice<AnisotropyMode>(
        "--anisotropy",
        {{"auto", AnisotropyMode::Auto}, {"isotropic", AnisotropyMode::Isotropic}, {"anisotropic", AnisotropyMode::Anisotropic}},
        recipe.writer.anisotropy, "is not auto, isotropic or anisotropic");
    recipe.writer.phi_count = int(cl.whole("--phi", 3, 4096, recipe.writer.phi_count));
    recipe.writer.theta_count = int(cl.whole("--theta", 2, 4096, recipe.writer.theta_count));
    recipe.writer.ndf_size = int(cl.whole("--ndf", 2, 4096, recipe.writer.ndf_size));
    recipe.writer.ndf_rows = int(cl.whole("--ndf-rows", 2, 4096, recipe.writer.ndf_rows));
    recipe.writer.vndf_size = int(cl.whole("--vndf", 2, 4096, recipe.writer.vndf_size));
    recipe.writer.data_size = int(cl.whole("--data", 2, 4096, recipe.writer.data_size));
    recipe.writer.threads = int(cl.whole("--threads", 1, 4096, 0));
    if (recipe.writer.description.empty()) recipe.writer.description = recipe.material.name;
}

}  // namespace

int run_synth(const std::vector<std::string>& args) {
    const CommandLine cl = read_command_line(kHelp, kFlags, args);
    cl.expect_positional(0, 0, "no FILE arguments (options only)");
    // Nothing at all is a usage error; a missing -o is found once the recipe is read.
    if (args.empty()) throw UsageError("missing -o OUT.bsdf and the material (flags or --recipe)");

    MaterialRecipe recipe;
    recipe.writer.channels = Channels::spectral({});
    if (cl.has("--recipe")) {
        recipe = load_material_recipe(cl.value("--recipe"));
    } else {
        recipe.material.name = "synthetic material";
    }
    apply_lobe_flags(cl, recipe.material);
    apply_writer_flags(cl, recipe);

    const std::string output = cl.has("-o") ? cl.value("-o") : recipe.output;
    if (output.empty()) throw Error("", "no output file: give -o OUT.bsdf (or 'output' in the recipe)");
    if (recipe.material.specular.empty() && recipe.material.diffuse.empty() && recipe.material.retroreflection.empty() &&
        recipe.material.sheen.empty()) {
        throw Error("", "the material reflects nothing: give a recipe, a Fresnel/roughness or --diffuse");
    }

    FileUses uses;
    if (cl.has("--recipe")) uses.input(cl.value("--recipe"), "--recipe");
    uses.output(output, "-o").check();
    check_output_path(output);  // a destination that cannot be written fails now, not after the tabulation
    const AnalyticBrdf brdf = [&] {
        try {
            return AnalyticBrdf(recipe.material);
        } catch (const Error& e) {
            if (!cl.has("--recipe")) throw;
            throw Error(cl.value("--recipe"), e.problem());  // named by the recipe's file
        }
    }();
    recipe.writer.ndf = brdf.ndf_function();
    ProgressBar bar("synth " + output, !cl.has("--quiet"));
    if (bar.enabled()) recipe.writer.progress = [&bar](double f) { bar.update(f); };
    const RglWriteReport report = write_rgl(brdf, output, recipe.writer);
    bar.finish();
    std::printf("wrote %s: %s, %s, %zu phi_i x %zu theta_i, %.1f MiB, %.1f s\n", output.c_str(),
                report.isotropic ? "isotropic" : "anisotropic",
                recipe.writer.channels.is_rgb() ? "RGB" : (std::to_string(recipe.writer.channels.size()) + " wavelengths").c_str(),
                report.phi_i.size(), report.theta_i.size(), double(report.bytes) / (1024.0 * 1024.0), report.seconds);
    return 0;
}

}  // namespace npf::cli
