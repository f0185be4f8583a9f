// Edit steps, recipes and the edit history (docs/editing.md).
//
// A recipe is a YAML file (examples in configs/edits/):
//
//   description: brushed copper, stretched   # optional: the edited material's description
//   steps:                                    # applied in order
//     - stretch: {tangent: 2, bitangent: 1}
//     - rotate: 30                            # degrees
//     - roughness: 0.5                        # or sharpen: 2, blur: 2
//     - matrix: [[1, 0.3, 0], [0, 1, 0], [0, 0, 1]]
//     - diffuse: {from: felt.exr}             # or {srgb: [r, g, b]}, {linear_srgb: ...},
//                                             #    {spectrum: file.spd | [[nm, v], ...]}
//     - specular: {from: gold.exr, keep_brightness: true}
//     - thin_film: {thickness: 615, film_ior: 1.3, base: fitted, mode: ratio}
//     - compress: {rank: [8, 6]}               # or {pca: [0.99, 0.95]}: D, G re-compressed
//     - limit_albedo: 1                       # or {cap: 0.95}: G lowered where the albedo exceeds it
//   options: {phi_cells: 180, svd: rank, albedo_tolerance: 0.005}
//
// Paths are relative to the recipe's folder. Errors name "recipe.yaml:LINE" and the key. The step
// keys are the edit kinds' (edit_kinds.h; one file each in edit/src/kinds/).
#pragma once

#include <npf/core/directional_albedo.h>
#include <npf/edit/albedo_limit.h>
#include <npf/edit/edit_kinds.h>
#include <npf/edit/edit_record.h>
#include <npf/edit/edit_step.h>
#include <npf/edit/ndf_transform.h>
#include <npf/edit/thin_film.h>
#include <npf/shading/npf_model.h>

#include <functional>
#include <string>
#include <vector>

namespace npf::edit {

struct EditOptions {
    NdfTransformOptions ndf;
    bool check_albedo = true;
    double albedo_tolerance = 0.005;  // warn when a step takes the directional albedo above 1 + this
    // The check after each step: the default views (default_albedo_thetas) and threads.
    AlbedoTableOptions albedo;
    std::string description;  // non-empty: replaces the `description` metadata
    // Long steps (limit_albedo on a large anisotropic material) report the fraction done here.
    std::function<void(double)> progress;
};

struct EditRecipe {
    std::vector<EditStep> steps;
    EditOptions options;
    bool has_description = false;  // the recipe set options.description
    // Which options the recipe set (so that command-line flags can override the others only).
    bool has_phi_cells = false, has_svd = false, has_albedo_tolerance = false;
};

// Throws npf::Error naming "file:line" and the key for malformed YAML, unknown keys, values of
// the wrong kind or out of range, and spectra files that cannot be read. Materials named by
// `from` are read when the step is applied (errors then name the recipe line too).
EditRecipe load_edit_recipe(const std::string& path);
// The same from YAML text; `source` names it in errors and `base_dir` resolves relative paths.
EditRecipe parse_edit_recipe(const std::string& yaml, const std::string& source, const std::string& base_dir);
// The same with the steps of `kinds` instead of edit_kinds() (edit_kinds.h).
EditRecipe parse_edit_recipe(const std::string& yaml, const std::string& source, const std::string& base_dir,
                             const EditKinds& kinds);

// A thin-film base from text: "fitted", a number (a dielectric's index), "eta,k", or a metal of
// the shipped tables (Ag, Al, Au, Cr, Cu). Throws npf::Error naming `what`.
FilmBase parse_film_base(const std::string& text, const std::string& what);

struct EditResult {
    NpfModel model;
    std::vector<EditRecord> records;  // one per step, in order
    AlbedoPeak input_albedo, output_albedo;  // when options.check_albedo
    std::vector<std::string> history_keys;    // the metadata keys added (edit_001, ...)
};

// Applies the steps in order, each to the result of the previous. After each step the
// directional albedo is checked (options.check_albedo, the default views, the one estimator of
// directional_albedo.h): a step that takes it above 1 + tolerance, or raises an excess the
// material already had by more than the tolerance, gets a warning in its record. Appends one metadata entry per step, "edit_NNN" (numbered on from the
// highest already in the model, so a file edited twice keeps both histories), whose value is the
// step's label, its summary, the largest albedo and any warnings. `on_step` (optional) sees each
// record as it is made. Throws npf::Error naming the step's origin.
EditResult apply_edits(const NpfModel& model, const std::vector<EditStep>& steps, const EditOptions& options = {},
                       const std::function<void(std::size_t, const EditRecord&)>& on_step = {});

// The model's edit history: the values of its edit_NNN metadata, in order.
std::vector<std::pair<std::string, std::string>> edit_history(const NpfModel& model);

}  // namespace npf::edit
