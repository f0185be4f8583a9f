// Material recipes: every spectrum and Fresnel form of the recipe language, and the helpers the
// `npf synth` flags share with the recipes (spectrum_from_text, conductor_fresnel).

#include "recipe_checks.h"
#include "synthetic_rgl.h"

#include <npf/color/spectrum.h>
#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/materials/analytic/fresnel.h>
#include <npf/materials/material_recipe.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using namespace npf::testing::recipe;

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
