// Analytic material recipes: a short YAML description of an analytic material and of the RGL
// file to make from it (`npf synth`). The format is documented in docs/synth.md; examples are
// in configs/materials/.
#pragma once

#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/materials/rgl_writer.h>

#include <string>

namespace npf {

// The wavelengths written when neither a recipe nor a flag says: the RGL database's range.
extern const char* const kDefaultWavelengths;  // "360:1000:195"

struct MaterialRecipe {
    AnalyticMaterial material;
    RglWriterOptions writer;   // channels, grid sizes, anisotropy; ndf/progress left empty
    std::string output;        // from the recipe's `output`, resolved against its folder; may be ""
};

// Throws npf::Error naming "file:line" and the key for malformed or unknown entries.
MaterialRecipe load_material_recipe(const std::string& path);
// The same from YAML text; `source` names it in errors and `base_dir` resolves relative paths.
MaterialRecipe parse_material_recipe(const std::string& yaml, const std::string& source, const std::string& base_dir);

// The pieces of the recipe language, shared with the command-line flags of `npf synth`.
// A spectrum: a number (constant), "r,g,b" sRGB-encoded colour, or a .spd file path.
color::SampledSpectrum spectrum_from_text(const std::string& text, const std::string& what);
// A conductor's Fresnel from a metal name ("Cu", looked up in the shipped ior/ tables).
Fresnel conductor_fresnel(const std::string& metal, const std::string& what);

}  // namespace npf
