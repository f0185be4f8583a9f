// Material recipes (npf/materials/material_recipe.h): the shipped recipes in configs/materials/,
// every spectrum and Fresnel form of the recipe language, the errors (which name "file:line",
// the key and the problem), and the helpers the `npf synth` flags share with the recipes
// (spectrum_from_text, conductor_fresnel).
// Here the shipped recipes and the recipe language; spectra, Fresnel forms and the flag helpers:
// test_material_recipe_spectra.cpp; the errors: test_material_recipe_errors.cpp.

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

}  // namespace
