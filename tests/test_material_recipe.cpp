// Material recipes (npf/materials/material_recipe.h): the shipped recipes in configs/materials/,
// every spectrum and Fresnel form of the recipe language, the errors (which name "file:line",
// the key and the problem), and the helpers the `npf synth` flags share with the recipes
// (spectrum_from_text, conductor_fresnel).
#include "synthetic_rgl.h"

#include <npf/color/spectrum.h>
#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/materials/analytic/fresnel.h>
#include <npf/materials/data_files.h>
#include <npf/materials/material_recipe.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using npf::Fresnel;
using npf::MaterialRecipe;
using npf::MicrofacetDistribution;
using npf::color::SampledSpectrum;

constexpr double kPi = npf::kPiD;
const std::string kShipped = std::string(NPF_SOURCE_DIR) + "/configs/materials";

MaterialRecipe parse(const std::string& yaml, const std::string& base_dir = "/recipes") {
    return npf::parse_material_recipe(yaml, "r.yaml", base_dir);
}

// The message of the npf::Error that parsing `yaml` throws ("" if none, with a test failure).
std::string error_of(const std::string& yaml) {
    try {
        parse(yaml);
    } catch (const npf::Error& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not an npf::Error: " << e.what() << "\nrecipe:\n" << yaml;
        return e.what();
    }
    ADD_FAILURE() << "no error for the recipe:\n" << yaml;
    return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Expects the error message of `yaml` to start with `prefix` (e.g. "r.yaml:3: key 'alpha': ")
// and to contain `problem`.
void expect_error(const std::string& yaml, const std::string& prefix, const std::string& problem) {
    const std::string e = error_of(yaml);
    EXPECT_EQ(e.rfind(prefix, 0), 0u) << "message: " << e << "\nexpected it to start with: " << prefix
                                      << "\nrecipe:\n" << yaml;
    EXPECT_TRUE(contains(e, problem)) << "message: " << e << "\nexpected it to contain: " << problem << "\nrecipe:\n"
                                      << yaml;
}

void write_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    ASSERT_FALSE(out.fail()) << "cannot write " << path;
}

const std::vector<double> kTestWavelengths = {380.0, 450.0, 532.0, 610.0, 700.0, 780.0};
const std::vector<double> kTestCosines = {0.05, 0.3, 0.7, 1.0};

// Both Fresnel terms agree at a few angles and wavelengths (relative 1e-9).
void expect_same_fresnel(const Fresnel& got, const Fresnel& want, const std::string& what) {
    EXPECT_EQ(int(got.kind()), int(want.kind())) << what;
    for (double l : kTestWavelengths) {
        for (double c : kTestCosines) {
            const double g = got.eval(c, l), w = want.eval(c, l);
            EXPECT_NEAR(g, w, 1e-9 * std::fabs(w) + 1e-12) << what << " at cos " << c << ", " << l << " nm";
        }
    }
}

void expect_same_spectrum(const SampledSpectrum& got, const SampledSpectrum& want, const std::string& what) {
    ASSERT_FALSE(got.empty()) << what;
    for (double l : {360.0, 380.0, 450.0, 500.0, 532.0, 610.0, 700.0, 780.0, 830.0}) {
        EXPECT_NEAR(got(l), want(l), 1e-12 + 1e-9 * std::fabs(want(l))) << what << " at " << l << " nm";
    }
}

SampledSpectrum constant(double v) { return SampledSpectrum::constant(v); }

SampledSpectrum srgb(double r, double g, double b) {
    using namespace npf::color;
    return linear_srgb_to_spectrum({srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b)});
}

SampledSpectrum shipped_ior(const std::string& metal, const std::string& part) {
    const std::string path = npf::find_data_file("ior/" + metal + "." + part + ".spd");
    EXPECT_FALSE(path.empty()) << "ior/" << metal << "." << part << ".spd not found";
    return path.empty() ? constant(1.0) : npf::color::read_spd(path);
}

Fresnel metal(const std::string& name) { return Fresnel::conductor(shipped_ior(name, "eta"), shipped_ior(name, "k")); }

void expect_grid(const npf::RglWriterOptions& w, int phi, int theta, int ndf, int ndf_rows, int vndf, int data) {
    EXPECT_EQ(w.phi_count, phi);
    EXPECT_EQ(w.theta_count, theta);
    EXPECT_EQ(w.ndf_size, ndf);
    EXPECT_EQ(w.ndf_rows, ndf_rows);
    EXPECT_EQ(w.vndf_size, vndf);
    EXPECT_EQ(w.data_size, data);
}

void expect_spectral_range(const MaterialRecipe& r, std::size_t count, float first, float last) {
    ASSERT_FALSE(r.writer.channels.is_rgb());
    const std::vector<float>& w = r.writer.channels.wavelengths();
    ASSERT_EQ(w.size(), count);
    EXPECT_FLOAT_EQ(w.front(), first);
    EXPECT_FLOAT_EQ(w.back(), last);
    EXPECT_EQ(r.material.wavelengths, w);  // the material reports the file's wavelengths
}

// ---- The shipped recipes ------------------------------------------------------------------

TEST(MaterialRecipeShipped, EveryRecipeLoads) {
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(kShipped)) {
        if (entry.path().extension() != ".yaml") continue;
        ++count;
        SCOPED_TRACE(entry.path().string());
        MaterialRecipe r;
        ASSERT_NO_THROW(r = npf::load_material_recipe(entry.path().string()));
        EXPECT_FALSE(r.material.name.empty());
        EXPECT_EQ(r.writer.description, r.material.name);
        EXPECT_EQ(r.output, "");  // none names an output: -o decides
        EXPECT_FALSE(r.writer.channels.is_rgb());
        EXPECT_NO_THROW(npf::AnalyticBrdf{r.material});  // the material itself is valid
    }
    EXPECT_GE(count, 5);
}

TEST(MaterialRecipeShipped, BrushedCopper) {
    const MaterialRecipe r = npf::load_material_recipe(kShipped + "/brushed_copper.yaml");
    EXPECT_EQ(r.material.name, "brushed copper (analytic, npf synth)");
    expect_spectral_range(r, 195, 360.f, 1000.f);
    ASSERT_EQ(r.material.specular.size(), 1u);
    const npf::SpecularLobe& lobe = r.material.specular[0];
    EXPECT_EQ(lobe.ndf.type, MicrofacetDistribution::Ggx);
    EXPECT_FLOAT_EQ(lobe.ndf.alpha_x, 0.08f);
    EXPECT_FLOAT_EQ(lobe.ndf.alpha_y, 0.35f);
    EXPECT_FLOAT_EQ(lobe.ndf.rotation, 0.f);
    expect_same_fresnel(lobe.fresnel, metal("Cu"), "Cu");
    expect_same_spectrum(lobe.weight, constant(1.0), "default weight");
    expect_same_spectrum(r.material.diffuse, constant(0.01), "diffuse");
    EXPECT_TRUE(r.material.retroreflection.empty());
    EXPECT_TRUE(r.material.sheen.empty());
    expect_grid(r.writer, 24, 8, 128, 64, 128, 32);
    EXPECT_EQ(r.writer.anisotropy, npf::AnisotropyMode::Auto);
}

TEST(MaterialRecipeShipped, CrossedLobesFailureCase) {
    const MaterialRecipe r = npf::load_material_recipe(kShipped + "/crossed_lobes_failure.yaml");
    EXPECT_EQ(r.material.name, "crossed lobes + retro-reflection (NPF failure case)");
    expect_spectral_range(r, 41, 380.f, 780.f);
    ASSERT_EQ(r.material.specular.size(), 2u);
    const npf::SpecularLobe& a = r.material.specular[0];
    const npf::SpecularLobe& b = r.material.specular[1];
    EXPECT_EQ(a.ndf.type, MicrofacetDistribution::Ggx);
    EXPECT_EQ(b.ndf.type, MicrofacetDistribution::Beckmann);
    for (const npf::SpecularLobe* l : {&a, &b}) {
        EXPECT_FLOAT_EQ(l->ndf.alpha_x, 0.06f);
        EXPECT_FLOAT_EQ(l->ndf.alpha_y, 0.3f);
    }
    EXPECT_FLOAT_EQ(a.ndf.rotation, 0.f);
    EXPECT_FLOAT_EQ(b.ndf.rotation, float(kPi / 2));  // 90 degrees
    expect_same_fresnel(a.fresnel, metal("Au"), "Au");
    expect_same_fresnel(b.fresnel, metal("Ag"), "Ag");
    expect_same_spectrum(a.weight, constant(1.0), "first weight");
    expect_same_spectrum(b.weight, constant(0.6), "second weight");
    expect_same_spectrum(r.material.diffuse, constant(0.02), "diffuse");
    expect_same_spectrum(r.material.retroreflection, constant(0.15), "retro weight");
    EXPECT_FLOAT_EQ(r.material.retro_exponent, 12.f);
    // ndf and ndf_rows are not given: the writer's defaults stay.
    expect_grid(r.writer, 24, 8, 128, 64, 96, 32);
}

TEST(MaterialRecipeShipped, RedPlastic) {
    const MaterialRecipe r = npf::load_material_recipe(kShipped + "/red_plastic.yaml");
    EXPECT_EQ(r.material.name, "red plastic (analytic, npf synth)");
    expect_spectral_range(r, 41, 380.f, 780.f);
    ASSERT_EQ(r.material.specular.size(), 1u);
    const npf::SpecularLobe& lobe = r.material.specular[0];
    EXPECT_FLOAT_EQ(lobe.ndf.alpha_x, 0.1f);
    EXPECT_FLOAT_EQ(lobe.ndf.alpha_y, 0.1f);
    expect_same_fresnel(lobe.fresnel, Fresnel::dielectric(constant(1.5)), "dielectric 1.5");
    expect_same_spectrum(r.material.diffuse, srgb(0.8, 0.08, 0.05), "diffuse");
    EXPECT_GT(r.material.diffuse(650.0), 4.0 * r.material.diffuse(450.0));  // red
    expect_grid(r.writer, 24, 8, 128, 64, 128, 32);                          // no grid: defaults
}

TEST(MaterialRecipeShipped, SatinFabric) {
    const MaterialRecipe r = npf::load_material_recipe(kShipped + "/satin_fabric.yaml");
    EXPECT_EQ(r.material.name, "blue satin (analytic, npf synth)");
    expect_spectral_range(r, 41, 380.f, 780.f);
    ASSERT_EQ(r.material.specular.size(), 1u);
    const npf::SpecularLobe& lobe = r.material.specular[0];
    EXPECT_FLOAT_EQ(lobe.ndf.alpha_x, 0.12f);
    EXPECT_FLOAT_EQ(lobe.ndf.alpha_y, 0.55f);
    EXPECT_FLOAT_EQ(lobe.ndf.rotation, float(kPi / 2));
    expect_same_fresnel(lobe.fresnel, Fresnel::dielectric(constant(1.45)), "dielectric 1.45");
    expect_same_spectrum(lobe.weight, srgb(0.75, 0.8, 1.0), "lobe weight");
    expect_same_spectrum(r.material.diffuse, srgb(0.08, 0.12, 0.45), "diffuse");
    expect_same_spectrum(r.material.sheen, constant(0.15), "sheen");
    expect_grid(r.writer, 24, 8, 128, 64, 96, 32);
}

TEST(MaterialRecipeShipped, ThinFilmAluminium) {
    const MaterialRecipe r = npf::load_material_recipe(kShipped + "/thin_film_aluminium.yaml");
    expect_spectral_range(r, 95, 360.f, 830.f);
    ASSERT_EQ(r.material.specular.size(), 1u);
    const npf::SpecularLobe& lobe = r.material.specular[0];
    EXPECT_FLOAT_EQ(lobe.ndf.alpha_x, 0.1f);
    EXPECT_FLOAT_EQ(lobe.ndf.alpha_y, 0.2f);
    expect_same_fresnel(lobe.fresnel,
                        Fresnel::thin_film(450.0, constant(1.33), shipped_ior("Al", "eta"), shipped_ior("Al", "k")),
                        "thin film on Al");
    EXPECT_TRUE(r.material.diffuse.empty());
    expect_grid(r.writer, 24, 8, 128, 64, 96, 32);
}

// ---- The recipe language --------------------------------------------------------------------

TEST(MaterialRecipeParse, MinimalRecipeDefaults) {
    const MaterialRecipe r = parse("diffuse: 0.5\n");
    // No wavelengths: the database's 195 over 360..1000 nm, as for the flags.
    ASSERT_FALSE(r.writer.channels.is_rgb());
    EXPECT_EQ(r.writer.channels.size(), 195u);
    EXPECT_EQ(r.material.wavelengths.front(), 360.f);
    EXPECT_EQ(r.material.wavelengths.back(), 1000.f);
    EXPECT_TRUE(r.material.specular.empty());
    EXPECT_EQ(r.material.name, npf::AnalyticMaterial().name);
    EXPECT_EQ(r.writer.description, r.material.name);
    EXPECT_EQ(r.output, "");
    EXPECT_EQ(r.writer.anisotropy, npf::AnisotropyMode::Auto);
    expect_grid(r.writer, 24, 8, 128, 64, 128, 32);
    EXPECT_FALSE(r.writer.ndf);
    EXPECT_FALSE(r.writer.progress);
}

TEST(MaterialRecipeParse, LobeDefaults) {
    const MaterialRecipe r = parse("lobes:\n  - alpha: 0.25\n");
    ASSERT_EQ(r.material.specular.size(), 1u);
    const npf::SpecularLobe& lobe = r.material.specular[0];
    EXPECT_EQ(lobe.ndf.type, MicrofacetDistribution::Ggx);
    EXPECT_FLOAT_EQ(lobe.ndf.alpha_x, 0.25f);
    EXPECT_FLOAT_EQ(lobe.ndf.alpha_y, 0.25f);
    EXPECT_FLOAT_EQ(lobe.ndf.rotation, 0.f);
    EXPECT_EQ(lobe.fresnel.kind(), Fresnel::Kind::One);
    expect_same_spectrum(lobe.weight, constant(1.0), "weight");
}

TEST(MaterialRecipeParse, RotationDegreesToRadians) {
    const MaterialRecipe r = parse("lobes:\n  - {alpha: [0.1, 0.3], rotation: 30}\n  - {alpha: 0.2, rotation: -45.5}\n");
    ASSERT_EQ(r.material.specular.size(), 2u);
    EXPECT_NEAR(r.material.specular[0].ndf.rotation, kPi / 6, 1e-6);
    EXPECT_NEAR(r.material.specular[1].ndf.rotation, -45.5 * kPi / 180, 1e-6);
}

TEST(MaterialRecipeParse, Distributions) {
    const MaterialRecipe r = parse("lobes:\n  - {distribution: beckmann, alpha: 0.3}\n  - {distribution: ggx, alpha: 0.3}\n");
    ASSERT_EQ(r.material.specular.size(), 2u);
    EXPECT_EQ(r.material.specular[0].ndf.type, MicrofacetDistribution::Beckmann);
    EXPECT_EQ(r.material.specular[1].ndf.type, MicrofacetDistribution::Ggx);
}

TEST(MaterialRecipeParse, AlphaLimitsAreInclusive) {
    const MaterialRecipe r = parse("lobes:\n  - alpha: [0.0001, 4]\n");
    EXPECT_FLOAT_EQ(r.material.specular[0].ndf.alpha_x, 1e-4f);
    EXPECT_FLOAT_EQ(r.material.specular[0].ndf.alpha_y, 4.f);
}

TEST(MaterialRecipeParse, Wavelengths) {
    MaterialRecipe r = parse("wavelengths: rgb\ndiffuse: 0.5\n");
    EXPECT_TRUE(r.writer.channels.is_rgb());
    EXPECT_TRUE(r.material.wavelengths.empty());

    r = parse("wavelengths: 400:700:4\ndiffuse: 0.5\n");
    EXPECT_EQ(r.writer.channels.wavelengths(), (std::vector<float>{400.f, 500.f, 600.f, 700.f}));
    EXPECT_EQ(r.material.wavelengths, r.writer.channels.wavelengths());

    r = parse("wavelengths: [450, 550.5, 650]\ndiffuse: 0.5\n");
    EXPECT_EQ(r.writer.channels.wavelengths(), (std::vector<float>{450.f, 550.5f, 650.f}));

    r = parse("wavelengths: 450,550,650\ndiffuse: 0.5\n");  // the command-line list form
    EXPECT_EQ(r.writer.channels.wavelengths(), (std::vector<float>{450.f, 550.f, 650.f}));
}

TEST(MaterialRecipeParse, GridAndAnisotropy) {
    MaterialRecipe r = parse("diffuse: 0.5\ngrid: {phi: 5, theta: 4, ndf: 32, ndf_rows: 8, vndf: 24, data: 8}\n"
                             "anisotropy: anisotropic\n");
    expect_grid(r.writer, 5, 4, 32, 8, 24, 8);
    EXPECT_EQ(r.writer.anisotropy, npf::AnisotropyMode::Anisotropic);
    r = parse("diffuse: 0.5\ngrid:\n  phi: 3.0\n  theta: 2\n  data: 4096\nanisotropy: isotropic\n");
    EXPECT_EQ(r.writer.phi_count, 3);  // 3.0 is a whole number
    EXPECT_EQ(r.writer.theta_count, 2);
    EXPECT_EQ(r.writer.data_size, 4096);
    EXPECT_EQ(r.writer.anisotropy, npf::AnisotropyMode::Isotropic);
    r = parse("diffuse: 0.5\nanisotropy: auto\n");
    EXPECT_EQ(r.writer.anisotropy, npf::AnisotropyMode::Auto);
}

TEST(MaterialRecipeParse, NameAndOutput) {
    MaterialRecipe r = parse("name: shiny thing\noutput: out/shiny.bsdf\ndiffuse: 0.5\n", "/some/folder");
    EXPECT_EQ(r.material.name, "shiny thing");
    EXPECT_EQ(r.writer.description, "shiny thing");
    EXPECT_EQ(r.output, "/some/folder/out/shiny.bsdf");  // relative to the recipe's folder
    r = parse("output: /abs/shiny.bsdf\ndiffuse: 0.5\n", "/some/folder");
    EXPECT_EQ(r.output, "/abs/shiny.bsdf");
}

TEST(MaterialRecipeParse, OtherLobes) {
    const MaterialRecipe r = parse("retroreflection: {weight: 0.2, exponent: 7.5}\nsheen: {linear_srgb: [0.1, 0.2, 0.3]}\n");
    expect_same_spectrum(r.material.retroreflection, constant(0.2), "retro");
    EXPECT_FLOAT_EQ(r.material.retro_exponent, 7.5f);
    expect_same_spectrum(r.material.sheen, npf::color::linear_srgb_to_spectrum({0.1, 0.2, 0.3}), "sheen");
    EXPECT_TRUE(r.material.diffuse.empty());
    // The exponent is optional.
    EXPECT_FLOAT_EQ(parse("retroreflection: {weight: 0.2}\n").material.retro_exponent, npf::AnalyticMaterial().retro_exponent);
}

// ---- Spectra ----------------------------------------------------------------------------------

TEST(MaterialRecipeSpectrum, Number) {
    expect_same_spectrum(parse("diffuse: 0.25\n").material.diffuse, constant(0.25), "number");
    expect_same_spectrum(parse("diffuse: 1\n").material.diffuse, constant(1.0), "integer");
    expect_same_spectrum(parse("diffuse: 2.5e-1\n").material.diffuse, constant(0.25), "exponent");
}

TEST(MaterialRecipeSpectrum, Srgb) {
    const SampledSpectrum s = parse("diffuse: {srgb: [0.8, 0.08, 0.05]}\n").material.diffuse;
    expect_same_spectrum(s, srgb(0.8, 0.08, 0.05), "srgb");
    // sRGB-encoded: 0.5 encoded is about 0.214 linear, a grey.
    const SampledSpectrum grey = parse("diffuse: {srgb: [0.5, 0.5, 0.5]}\n").material.diffuse;
    EXPECT_NEAR(grey(550.0), npf::color::srgb_to_linear(0.5), 0.01);
    EXPECT_NEAR(grey(450.0), grey(650.0), 0.01);
}

TEST(MaterialRecipeSpectrum, LinearSrgb) {
    const SampledSpectrum s = parse("diffuse: {linear_srgb: [0.1, 0.4, 0.9]}\n").material.diffuse;
    expect_same_spectrum(s, npf::color::linear_srgb_to_spectrum({0.1, 0.4, 0.9}), "linear_srgb");
    EXPECT_GT(s(450.0), s(650.0));  // bluish
    const SampledSpectrum grey = parse("diffuse: {linear_srgb: [0.5, 0.5, 0.5]}\n").material.diffuse;
    EXPECT_NEAR(grey(550.0), 0.5, 0.01);
}

TEST(MaterialRecipeSpectrum, Samples) {
    const SampledSpectrum s = parse("diffuse: {spectrum: [[400, 0.1], [550, 0.4], [700, 0.7]]}\n").material.diffuse;
    EXPECT_EQ(s.wavelengths(), (std::vector<double>{400.0, 550.0, 700.0}));
    EXPECT_EQ(s.values(), (std::vector<double>{0.1, 0.4, 0.7}));
    EXPECT_NEAR(s(475.0), 0.25, 1e-12);  // linear in between
    // Block style.
    const SampledSpectrum b = parse("diffuse:\n  spectrum:\n    - [400, 0.2]\n    - [700, 0.3]\n").material.diffuse;
    EXPECT_EQ(b.values(), (std::vector<double>{0.2, 0.3}));
}

TEST(MaterialRecipeSpectrum, FileRelativeToTheRecipe) {
    const std::string dir = npf::testing::temporary_folder("recipe_spd");
    std::filesystem::create_directories(dir + "/spectra");
    write_file(dir + "/spectra/ramp.spd", "# a ramp\n400 0.1\n500 0.3\n700 0.9\n");
    write_file(dir + "/recipe.yaml", "name: from a file\ndiffuse: {file: spectra/ramp.spd}\n");
    const MaterialRecipe r = npf::load_material_recipe(dir + "/recipe.yaml");
    EXPECT_EQ(r.material.diffuse.wavelengths(), (std::vector<double>{400.0, 500.0, 700.0}));
    EXPECT_EQ(r.material.diffuse.values(), (std::vector<double>{0.1, 0.3, 0.9}));

    // parse_material_recipe resolves against base_dir; absolute paths stay as they are.
    EXPECT_EQ(parse("diffuse: {file: ramp.spd}\n", dir + "/spectra").material.diffuse.values().size(), 3u);
    EXPECT_EQ(parse("diffuse: {file: " + dir + "/spectra/ramp.spd}\n", "/elsewhere").material.diffuse.values().size(), 3u);

    // A recipe loaded from the current folder (no slash in the path) resolves against ".".
    const std::filesystem::path cwd = std::filesystem::current_path();
    std::filesystem::current_path(dir);
    MaterialRecipe here;
    EXPECT_NO_THROW(here = npf::load_material_recipe("recipe.yaml"));
    std::filesystem::current_path(cwd);
    EXPECT_EQ(here.material.diffuse.values().size(), 3u);

    // A missing file names the path it looked for.
    const std::string e = error_of("diffuse: {file: nothing_here.spd}\n");
    EXPECT_TRUE(contains(e, "/recipes/nothing_here.spd")) << e;
    EXPECT_TRUE(contains(e, "not found")) << e;
}

TEST(MaterialRecipeSpectrum, SpectraInEveryPlace) {
    const MaterialRecipe r = parse(
        "lobes:\n"
        "  - alpha: 0.3\n"
        "    weight: {spectrum: [[400, 0.5], [700, 1.0]]}\n"
        "    fresnel: {schlick: {linear_srgb: [0.9, 0.6, 0.3]}}\n"
        "retroreflection: {weight: {srgb: [0.2, 0.2, 0.2]}}\n");
    expect_same_spectrum(r.material.specular[0].weight, SampledSpectrum({400.0, 700.0}, {0.5, 1.0}), "weight");
    expect_same_fresnel(r.material.specular[0].fresnel,
                        Fresnel::schlick(npf::color::linear_srgb_to_spectrum({0.9, 0.6, 0.3})), "schlick");
    expect_same_spectrum(r.material.retroreflection, srgb(0.2, 0.2, 0.2), "retro");
}

// ---- Fresnel ----------------------------------------------------------------------------------

Fresnel fresnel_of(const std::string& fresnel_yaml) {
    const MaterialRecipe r = parse("lobes:\n  - alpha: 0.2\n    fresnel: " + fresnel_yaml + "\n");
    EXPECT_EQ(r.material.specular.size(), 1u);
    return r.material.specular.empty() ? Fresnel::one() : r.material.specular[0].fresnel;
}

TEST(MaterialRecipeFresnel, ConductorByName) {
    for (const char* m : {"Ag", "Al", "Au", "Cr", "Cu"}) {
        expect_same_fresnel(fresnel_of(std::string("{conductor: ") + m + "}"), metal(m), m);
    }
    // Copper is red: it reflects more at 700 nm than at 450 nm.
    const Fresnel cu = fresnel_of("{conductor: Cu}");
    EXPECT_GT(cu.eval(1.0, 700.0), cu.eval(1.0, 450.0) + 0.2);
}

TEST(MaterialRecipeFresnel, ConductorByIndex) {
    expect_same_fresnel(fresnel_of("{conductor: {eta: 0.2, k: 3.5}}"), Fresnel::conductor(constant(0.2), constant(3.5)),
                        "eta, k");
    expect_same_fresnel(fresnel_of("{conductor: {eta: {spectrum: [[400, 1.2], [700, 0.2]]}, k: 3}}"),
                        Fresnel::conductor(SampledSpectrum({400.0, 700.0}, {1.2, 0.2}), constant(3.0)), "eta spectrum");
}

TEST(MaterialRecipeFresnel, DielectricSchlickOne) {
    expect_same_fresnel(fresnel_of("{dielectric: 1.5}"), Fresnel::dielectric(constant(1.5)), "dielectric");
    expect_same_fresnel(fresnel_of("{schlick: 0.04}"), Fresnel::schlick(constant(0.04)), "schlick number");
    expect_same_fresnel(fresnel_of("{schlick: {srgb: [0.9, 0.6, 0.3]}}"), Fresnel::schlick(srgb(0.9, 0.6, 0.3)),
                        "schlick srgb");
    expect_same_fresnel(fresnel_of("{one: ~}"), Fresnel::one(), "one");
    EXPECT_DOUBLE_EQ(fresnel_of("{one: true}").eval(0.3, 500.0), 1.0);
}

TEST(MaterialRecipeFresnel, ThinFilmBases) {
    expect_same_fresnel(fresnel_of("{thin_film: {thickness: 450, film_ior: 1.33, base: Al}}"),
                        Fresnel::thin_film(450.0, constant(1.33), shipped_ior("Al", "eta"), shipped_ior("Al", "k")),
                        "metal base");
    expect_same_fresnel(fresnel_of("{thin_film: {thickness: 300, film_ior: 1.4, base: 1.5}}"),
                        Fresnel::thin_film(300.0, constant(1.4), constant(1.5), constant(0.0)), "numeric base");
    expect_same_fresnel(fresnel_of("{thin_film: {thickness: 200, film_ior: 2.0, base: {eta: 1.2, k: 3.0}}}"),
                        Fresnel::thin_film(200.0, constant(2.0), constant(1.2), constant(3.0)), "eta, k base");
    expect_same_fresnel(fresnel_of("{thin_film: {thickness: 200, film_ior: 2.0, base: {eta: 1.6}}}"),
                        Fresnel::thin_film(200.0, constant(2.0), constant(1.6), constant(0.0)), "eta-only base");
    // Thickness 0 is allowed and gives the bare base.
    expect_same_fresnel(fresnel_of("{thin_film: {thickness: 0, film_ior: 1.33, base: Cu}}"),
                        Fresnel::thin_film(0.0, constant(1.33), shipped_ior("Cu", "eta"), shipped_ior("Cu", "k")),
                        "zero thickness");
    const Fresnel zero = fresnel_of("{thin_film: {thickness: 0, film_ior: 1.33, base: Cu}}");
    const Fresnel cu = metal("Cu");
    for (double l : kTestWavelengths) EXPECT_NEAR(zero.eval(0.7, l), cu.eval(0.7, l), 1e-6) << l;
    // Block style, as in the shipped recipe.
    const MaterialRecipe r = parse(
        "lobes:\n  - alpha: 0.2\n    fresnel:\n      thin_film:\n        thickness: 450\n        film_ior: 1.33\n"
        "        base: Al\n");
    EXPECT_EQ(r.material.specular[0].fresnel.kind(), Fresnel::Kind::ThinFilm);
}

// ---- Errors -----------------------------------------------------------------------------------

TEST(MaterialRecipeErrors, InvalidYaml) {
    expect_error("name: x\n\tdiffuse: 0.5\n", "r.yaml:2: not valid YAML", "tab");
    expect_error("name: x\nlobes:\n  - alpha: [0.1, 0.2\n    weight: 1\ndiffuse: 0.2\n", "r.yaml:", "not valid YAML");
    expect_error("name: x\ndiffuse: {linear_srgb: [0.5, 0.5, 0.5]\n", "r.yaml:", "not valid YAML");
    expect_error("name: x\n  diffuse: 0.5\n", "r.yaml:2: not valid YAML", "");
}

TEST(MaterialRecipeErrors, TopLevelNotAMapping) {
    for (const char* yaml : {"", "# only a comment\n", "- a\n- b\n", "just text\n", "42\n"}) {
        expect_error(yaml, "r.yaml: ", "a material recipe is a YAML mapping");
    }
}

TEST(MaterialRecipeErrors, UnknownKeys) {
    expect_error("name: x\ndiffuse: 0.5\ncolour: red\n", "r.yaml:3: key 'colour': ", "unknown key");
    expect_error("name: x\ncolour: red\n", "r.yaml:2: key 'colour': ",
                 "expected one of: name, output, wavelengths, lobes, diffuse, retroreflection, sheen, grid, anisotropy");
    expect_error("lobes:\n  - alpha: 0.1\n    roughness: 0.2\n", "r.yaml:3: key 'roughness': ", "unknown key");
    expect_error("lobes:\n  - alpha: 0.1\n    fresnel: {metal: Cu}\n", "r.yaml:3: key 'metal': ", "unknown key");
    expect_error("diffuse: 0.5\ngrid: {phi: 5, rows: 3}\n", "r.yaml:2: key 'rows': ", "unknown key");
    expect_error("diffuse: {rgb: [1, 0, 0]}\n", "r.yaml:1: key 'rgb': ", "unknown key");
    expect_error("retroreflection: {weight: 0.1, power: 3}\n", "r.yaml:1: key 'power': ", "unknown key");
    expect_error("lobes:\n  - alpha: 0.1\n    fresnel:\n      thin_film: {thickness: 1, film_ior: 1.3, base: Al, k: 2}\n",
                 "r.yaml:4: key 'k': ", "unknown key");
}

TEST(MaterialRecipeErrors, Alpha) {
    expect_error("lobes:\n  - alpha: 0\n", "r.yaml:2: key 'alpha': ", "roughness must lie in [1e-4, 4]");
    expect_error("lobes:\n  - alpha: -0.1\n", "r.yaml:2: key 'alpha': ", "roughness must lie in [1e-4, 4]");
    expect_error("lobes:\n  - alpha: 4.5\n", "r.yaml:2: key 'alpha': ", "roughness must lie in [1e-4, 4]");
    expect_error("lobes:\n  - alpha: [0.1, 5]\n", "r.yaml:2: key 'alpha': ", "roughness must lie in [1e-4, 4]");
    expect_error("lobes:\n  - alpha: [0.1, 0.2, 0.3]\n", "r.yaml:2: key 'alpha': ", "expected [alpha_x, alpha_y]");
    expect_error("lobes:\n  - alpha: [0.1]\n", "r.yaml:2: key 'alpha': ", "expected [alpha_x, alpha_y]");
    expect_error("lobes:\n  - alpha: rough\n", "r.yaml:2: key 'alpha': ", "'rough' is not a number");
    expect_error("lobes:\n  - alpha: {x: 0.1}\n", "r.yaml:2: key 'alpha': ", "expected a number");
    expect_error("lobes:\n  - alpha: .nan\n", "r.yaml:2: key 'alpha': ", "not a finite number");
    expect_error("lobes:\n  - distribution: ggx\n", "r.yaml:2: key 'lobes': ", "a lobe needs 'alpha'");
}

TEST(MaterialRecipeErrors, Distribution) {
    expect_error("lobes:\n  - alpha: 0.2\n    distribution: phong\n", "r.yaml:3: key 'distribution': ",
                 "'phong' is not ggx or beckmann");
    expect_error("lobes:\n  - alpha: 0.2\n    distribution: GGX\n", "r.yaml:3: key 'distribution': ",
                 "'GGX' is not ggx or beckmann");
}

TEST(MaterialRecipeErrors, UnknownMetal) {
    // The message names the recipe and the metal, and lists the shipped ones.
    const std::string e = error_of("lobes:\n  - alpha: 0.2\n    fresnel: {conductor: Xx}\n");
    EXPECT_EQ(e.rfind("r.yaml", 0), 0u) << e;
    EXPECT_TRUE(contains(e, "no refractive index tables for metal 'Xx'")) << e;
    EXPECT_TRUE(contains(e, "Ag, Al, Au, Cr, Cu")) << e;
    // A thin film's base names the line and the key.
    expect_error("lobes:\n  - alpha: 0.2\n    fresnel:\n      thin_film: {thickness: 100, film_ior: 1.3, base: Zz}\n",
                 "r.yaml:4: key 'base': ", "no refractive index tables for metal 'Zz'");
}

// An unknown conductor name is reported at the recipe's line and key, like every other error.
TEST(MaterialRecipeErrors, UnknownMetalNamesLineAndKey) {
    expect_error("lobes:\n  - alpha: 0.2\n    fresnel: {conductor: Xx}\n", "r.yaml:3: key 'conductor': ",
                 "no refractive index tables for metal 'Xx'");
}

TEST(MaterialRecipeErrors, Fresnel) {
    expect_error("lobes:\n  - alpha: 0.2\n    fresnel: {conductor: Cu, dielectric: 1.5}\n", "r.yaml:3: key 'fresnel': ",
                 "give exactly one of conductor, dielectric, schlick, thin_film, one");
    expect_error("lobes:\n  - alpha: 0.2\n    fresnel: {}\n", "r.yaml:3: key 'fresnel': ", "give exactly one of");
    expect_error("lobes:\n  - alpha: 0.2\n    fresnel: Cu\n", "r.yaml:3: key 'fresnel': ", "expected a mapping");
    expect_error("lobes:\n  - alpha: 0.2\n    fresnel: {conductor: {eta: 1.2}}\n", "r.yaml:3: key 'conductor': ",
                 "a conductor needs both eta and k");
    expect_error("lobes:\n  - alpha: 0.2\n    fresnel: {dielectric: glass}\n", "r.yaml:3: key 'dielectric': ",
                 "'glass' is not a number");
    expect_error("lobes:\n  - alpha: 0.2\n    fresnel:\n      thin_film:\n        thickness: -5\n"
                 "        film_ior: 1.3\n        base: Al\n",
                 "r.yaml:5: key 'thickness': ", "must not be negative");
    expect_error("lobes:\n  - alpha: 0.2\n    fresnel: {thin_film: {thickness: 100, base: Al}}\n",
                 "r.yaml:3: key 'thin_film': ", "missing 'film_ior'");
    expect_error("lobes:\n  - alpha: 0.2\n    fresnel: {thin_film: {thickness: 100, film_ior: 1.3, base: {k: 2}}}\n",
                 "r.yaml:3: key 'base': ", "missing 'eta'");
}

TEST(MaterialRecipeErrors, Spectra) {
    expect_error("diffuse: {srgb: [1, 0]}\n", "r.yaml:1: key 'srgb': ", "expected [r, g, b]");
    expect_error("diffuse: {linear_srgb: 0.5}\n", "r.yaml:1: key 'linear_srgb': ", "expected [r, g, b]");
    expect_error("diffuse: {srgb: [1, red, 0]}\n", "r.yaml:1: key 'srgb': ", "'red' is not a number");
    expect_error("diffuse: {srgb: [1, 1, 1], linear_srgb: [1, 1, 1]}\n", "r.yaml:1: key 'diffuse': ",
                 "give exactly one of srgb, linear_srgb, spectrum, file");
    expect_error("diffuse: {spectrum: []}\n", "r.yaml:1: key 'spectrum': ", "expected [[wavelength_nm, value], ...]");
    expect_error("diffuse:\n  spectrum:\n    - [400, 0.1]\n    - [500]\n", "r.yaml:4: key 'spectrum': ",
                 "each row is [wavelength_nm, value]");
    expect_error("diffuse: {spectrum: [[500, 0.5], [400, 0.5]]}\n", "r.yaml:1: key 'spectrum': ", "ascending");
    expect_error("diffuse: [0.1, 0.2, 0.3]\n", "r.yaml:1: key 'diffuse': ", "expected a mapping");
    expect_error("diffuse: .inf\n", "r.yaml:1: key 'diffuse': ", "not a finite number");
    expect_error("name: x\nsheen: shiny\n", "r.yaml:2: key 'sheen': ", "'shiny' is not a number");
}

TEST(MaterialRecipeErrors, Wavelengths) {
    expect_error("name: x\nwavelengths: 400:700\ndiffuse: 0.5\n", "r.yaml:2: key 'wavelengths': ",
                 "'400:700' must be start:end:count");
    expect_error("wavelengths: 400:700:1\ndiffuse: 0.5\n", "r.yaml:1: key 'wavelengths': ", "400:700:1");
    expect_error("wavelengths: visible\ndiffuse: 0.5\n", "r.yaml:1: key 'wavelengths': ", "visible");
    expect_error("wavelengths: 0:700:5\ndiffuse: 0.5\n", "r.yaml:1: key 'wavelengths': ", "not a positive number");
    expect_error("wavelengths: []\ndiffuse: 0.5\n", "r.yaml:1: key 'wavelengths': ", "expected rgb, start:end:count or a list");
    expect_error("wavelengths: {from: 400}\ndiffuse: 0.5\n", "r.yaml:1: key 'wavelengths': ", "expected rgb");
    expect_error("wavelengths: [400, blue]\ndiffuse: 0.5\n", "r.yaml:1: key 'wavelengths': ", "'blue' is not a number");
}

TEST(MaterialRecipeErrors, Grid) {
    expect_error("diffuse: 0.5\ngrid: {phi: 3.5}\n", "r.yaml:2: key 'phi': ", "expected a whole number in [3, 4096]");
    expect_error("diffuse: 0.5\ngrid:\n  phi: 24\n  theta: 1\n", "r.yaml:4: key 'theta': ",
                 "expected a whole number in [2, 4096]");
    expect_error("diffuse: 0.5\ngrid:\n  ndf: 5000\n", "r.yaml:3: key 'ndf': ", "expected a whole number in [2, 4096]");
    expect_error("diffuse: 0.5\ngrid: {phi: 2}\n", "r.yaml:2: key 'phi': ", "[3, 4096]");
    expect_error("diffuse: 0.5\ngrid: {vndf: many}\n", "r.yaml:2: key 'vndf': ", "'many' is not a number");
    expect_error("diffuse: 0.5\ngrid: {data: -8}\n", "r.yaml:2: key 'data': ", "whole number");
    expect_error("diffuse: 0.5\ngrid: {ndf_rows: 1e9}\n", "r.yaml:2: key 'ndf_rows': ", "whole number");
    expect_error("diffuse: 0.5\ngrid: 32\n", "r.yaml:2: key 'grid': ", "expected a mapping");
}

TEST(MaterialRecipeErrors, Anisotropy) {
    expect_error("diffuse: 0.5\nanisotropy: maybe\n", "r.yaml:2: key 'anisotropy': ",
                 "'maybe' is not auto, isotropic or anisotropic");
    expect_error("diffuse: 0.5\nanisotropy: [auto]\n", "r.yaml:2: key 'anisotropy': ", "expected text");
}

TEST(MaterialRecipeErrors, Structure) {
    expect_error("name: [a, b]\ndiffuse: 0.5\n", "r.yaml:1: key 'name': ", "expected text");
    expect_error("diffuse: 0.5\noutput: {path: x}\n", "r.yaml:2: key 'output': ", "expected text");
    expect_error("name: x\nlobes: {alpha: 0.2}\n", "r.yaml:2: key 'lobes': ", "expected a list of lobes");
    // An empty value is reported at its key's line.
    expect_error("name: x\nlobes:\n", "r.yaml:2: key 'lobes': ", "has no value");
    expect_error("lobes:\n  - 0.2\n", "r.yaml:2: key 'lobes': ", "expected a mapping");
    expect_error("retroreflection: 0.2\n", "r.yaml:1: key 'retroreflection': ", "expected a mapping");
    expect_error("retroreflection: {exponent: 4}\n", "r.yaml:1: key 'retroreflection': ", "missing 'weight'");
}

TEST(MaterialRecipeErrors, ReflectsNothing) {
    for (const char* yaml : {"name: x\n", "name: x\nlobes: []\nwavelengths: rgb\n", "grid: {phi: 5}\n"}) {
        expect_error(yaml, "r.yaml: ", "it reflects nothing");
    }
}

TEST(MaterialRecipeErrors, ExactLineNumbersInALongerRecipe) {
    const std::string head =
        "# a comment\n"                     // 1
        "name: test\n"                      // 2
        "wavelengths: 400:700:4\n"          // 3
        "\n"                                // 4
        "lobes:\n"                          // 5
        "  - distribution: ggx\n"           // 6
        "    alpha: [0.1, 0.2]\n"           // 7
        "    fresnel: {conductor: Cu}\n"    // 8
        "  - distribution: beckmann\n";     // 9
    expect_error(head + "    alpha: 0.3\n    weight: {srgb: [1, 1]}\n", "r.yaml:11: key 'srgb': ", "expected [r, g, b]");
    expect_error(head + "    alpha: [0.3, 0.00001]\n", "r.yaml:10: key 'alpha': ", "roughness");
    expect_error(head + "    alpha: 0.3\ndiffuse: 0.1\ngrid:\n  phi: 8\n  theta: 6\n  data: 7.5\n", "r.yaml:15: key 'data': ",
                 "whole number");
    expect_error(head + "    alpha: 0.3\n    rotation: ninety\n", "r.yaml:11: key 'rotation': ", "'ninety' is not a number");
    expect_error(head + "    alpha: 0.3\n\nsheen: 0.1\nbogus: 1\n", "r.yaml:13: key 'bogus': ", "unknown key");
}

TEST(MaterialRecipeErrors, LoadingFiles) {
    const std::string dir = npf::testing::temporary_folder("recipe_load");
    try {
        npf::load_material_recipe(dir + "/missing.yaml");
        ADD_FAILURE() << "no error for a missing recipe";
    } catch (const npf::Error& e) {
        EXPECT_EQ(std::string(e.what()), dir + "/missing.yaml: cannot open: file not found");
    }
    try {
        npf::load_material_recipe(dir);
        ADD_FAILURE() << "no error for a directory";
    } catch (const npf::Error& e) {
        EXPECT_EQ(std::string(e.what()), dir + ": is a directory, not a recipe");
    }
    // Errors in a loaded recipe name its path as given.
    write_file(dir + "/bad.yaml", "name: bad\nlobes:\n  - alpha: 9\n");
    try {
        npf::load_material_recipe(dir + "/bad.yaml");
        ADD_FAILURE() << "no error for a bad recipe";
    } catch (const npf::Error& e) {
        EXPECT_EQ(e.source(), dir + "/bad.yaml:3");
        EXPECT_TRUE(contains(e.problem(), "key 'alpha': roughness must lie in [1e-4, 4]")) << e.what();
    }
    // A recipe's `output` is relative to the recipe's folder.
    write_file(dir + "/good.yaml", "output: good.bsdf\ndiffuse: 0.5\n");
    EXPECT_EQ(npf::load_material_recipe(dir + "/good.yaml").output, dir + "/good.bsdf");
}

// Out-of-range values are caught by the parser and named at their line, not later by the
// material's constructor.
TEST(MaterialRecipeErrors, OutOfRangeValuesNameTheLine) {
    expect_error("name: x\ndiffuse: -0.5\n", "r.yaml:2: key 'diffuse': ", "negative value");
    expect_error("name: x\nwavelengths: [700, 400]\ndiffuse: 0.5\n", "r.yaml:2: key 'wavelengths': ", "ascending");
    expect_error("lobes:\n  - alpha: 0.2\n    fresnel: {dielectric: -1.5}\n", "r.yaml:3: key 'dielectric': ",
                 "negative value");
    expect_error("lobes:\n  - alpha: 0.2\n    fresnel: {schlick: 2}\n", "r.yaml:3: key 'schlick': ", "");
    expect_error("retroreflection: {weight: 0.1, exponent: -5}\n", "r.yaml:1: key 'exponent': ", "[0, 1e6]");
}

// A key given twice is an error (YAML parsers silently keep one of the values).
TEST(MaterialRecipeErrors, DuplicateKeys) {
    expect_error("lobes:\n  - alpha: 0.2\n    alpha: 0.3\n", "r.yaml:3: key 'alpha': ", "twice");
}

// ---- The helpers of the command-line flags ------------------------------------------------

TEST(MaterialRecipeHelpers, SpectrumFromText) {
    expect_same_spectrum(npf::spectrum_from_text("0.3", "--diffuse"), constant(0.3), "number");
    expect_same_spectrum(npf::spectrum_from_text("1e-2", "--diffuse"), constant(0.01), "exponent");
    expect_same_spectrum(npf::spectrum_from_text("0.8,0.08,0.05", "--diffuse"), srgb(0.8, 0.08, 0.05), "r,g,b");

    const std::string dir = npf::testing::temporary_folder("recipe_text");
    write_file(dir + "/s.spd", "400 0.2\n700 0.6\n");
    const SampledSpectrum f = npf::spectrum_from_text(dir + "/s.spd", "--diffuse");
    EXPECT_EQ(f.values(), (std::vector<double>{0.2, 0.6}));

    for (const char* bad : {"1,2", "0.1,0.2,0.3,0.4"}) {
        try {
            npf::spectrum_from_text(bad, "--diffuse");
            ADD_FAILURE() << "no error for '" << bad << "'";
        } catch (const npf::Error& e) {
            EXPECT_EQ(e.source(), "--diffuse");
            EXPECT_EQ(e.problem(), std::string("'") + bad + "' is neither one number nor an r,g,b colour");
        }
    }
    // Anything that is not a list of numbers is a file name.
    for (const std::string& bad : {dir + "/missing.spd", std::string("0.5,red,0.1"), std::string("")}) {
        try {
            npf::spectrum_from_text(bad, "--diffuse");
            ADD_FAILURE() << "no error for '" << bad << "'";
        } catch (const npf::Error& e) {
            EXPECT_TRUE(contains(e.what(), "not found")) << e.what();
        }
    }
    EXPECT_THROW(npf::spectrum_from_text(dir, "--diffuse"), npf::Error);  // a directory
}

TEST(MaterialRecipeHelpers, ConductorFresnel) {
    for (const char* m : {"Ag", "Al", "Au", "Cr", "Cu"}) {
        expect_same_fresnel(npf::conductor_fresnel(m, "--conductor"), metal(m), m);
    }
    try {
        npf::conductor_fresnel("Unobtainium", "--conductor");
        ADD_FAILURE() << "no error for an unknown metal";
    } catch (const npf::Error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "--conductor: no refractive index tables for metal 'Unobtainium' (shipped: Ag, Al, Au, Cr, Cu)");
    }
    EXPECT_THROW(npf::conductor_fresnel("", "--conductor"), npf::Error);
    EXPECT_THROW(npf::conductor_fresnel("cu", "--conductor"), npf::Error);  // names are case-sensitive
}

}  // namespace
