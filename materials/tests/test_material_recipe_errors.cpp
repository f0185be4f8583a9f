// Material recipes: the errors, which name "file:line", the key and the problem.

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

}  // namespace
