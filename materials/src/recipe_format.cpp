// Analytic material recipes (`.yaml`) as a material format: detection, loader
// (load_material_recipe, material_recipe.cpp, and AnalyticBrdf) and user documentation.
#include <npf/materials/material_formats.h>
#include <npf/materials/material_recipe.h>

#include <npf/core/error.h>
#include <npf/core/text.h>

namespace npf {

// Recipes by their name (a YAML file has no signature), evaluated exactly.
MaterialFormat recipe_material_format() {
    MaterialFormat f;
    f.claims_name = [](const std::string& path) { return ends_with(path, ".yaml") || ends_with(path, ".yml"); };
    f.open = [](const std::string& path) -> std::unique_ptr<Brdf> {
        const MaterialRecipe recipe = load_material_recipe(path);
        try {
            return std::make_unique<AnalyticBrdf>(recipe.material);
        } catch (const Error& e) {
            throw Error(path, e.problem());  // named by the recipe's file, not its material's name
        }
    };
    f.title = "Analytic recipes `.yaml` (`npf::AnalyticBrdf`, `materials/src/material_recipe.cpp`)";
    f.documentation = R"(**Reads** analytic material recipes (docs/synth.md; examples in `configs/materials/`), claimed
by their name alone (`.yaml`, `.yml`) before any file is opened: a diffuse term and microfacet
lobes (GGX or Beckmann, anisotropic and rotated, each with its conductor, dielectric, Schlick or
thin-film Fresnel), retro-reflection and sheen. The material is evaluated exactly, at any
wavelength or in RGB, and sampled by its lobes.

**Checks** every key against the keys its place allows, and ranges: roughness in [1e-4, 4],
weights, albedos and indices not negative, a film thickness not negative, a retro-reflection
exponent in [0, 1e6], a metal with shipped index tables (Ag, Al, Au, Cr, Cu), and a material that
reflects something. A refusal names the file, its line and the key.

**Limits.** The value bound of every material source (1e12) applies.

**Options:** `wavelengths`, `grid`, `anisotropy` and `output` only shape the RGL file `npf synth`
writes from the recipe; opening a recipe ignores them.
)";
    return f;
}

}  // namespace npf
