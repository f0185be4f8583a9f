// Batch configurations (`npf batch CONFIG.yaml`, docs/batch.md, configs/batch/example.yaml):
//
//   output_dir: out/library            # required; relative paths are taken from this file's folder
//   naming: "{name}.exr"               # optional; {name} is the material's name (its input's stem)
//   summary: out/library/summary       # optional; writes summary.json and summary.md
//   inputs:                            # required: paths and globs (*, ?, [...])
//     - ../../data/materials/*.bsdf
//     - ../materials/*.yaml
//   defaults:                          # optional: any `npf convert` setting, edit, render
//     preset: preview
//     threads: 2
//   materials:                         # optional: per-material overrides, by name
//     brushed_copper: {preset: production, edit: ../edits/rotate_anisotropy.yaml}
//     extra_one: {input: elsewhere/extra_one.bsdf}     # a material outside `inputs`
//     crossed_lobes_failure: {skip: true}
//
// Errors name "config.yaml:LINE" and the key.
#pragma once

#include <npf/converter/convert.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace npf::batch {

// One setting as given: its canonical text ("preview", "90,1,90,180", "0.99,0.95", "true") and
// where it was given ("config.yaml:12"), for errors raised when it is applied.
struct Setting {
    std::string value;
    std::string origin;
};
// Setting name -> setting. Names: the `npf convert` flags without dashes and with underscores
// (preset, wavelengths, max_wavelengths, isotropy, grid, g_grid, phi_d_samples, pca, rank,
// importance, compressive, epsilon, volume_weight, iterations, tolerance, g_prior, plain,
// error_pairs, target_psnr, threads), plus edit (a recipe's absolute path, or "" for none) and render
// ("true"/"false") with render.size, render.spp, render.seed, render.env, render.threads.
using Settings = std::map<std::string, Setting>;

// The names that are known, in the order the docs list them.
const std::vector<std::string>& setting_names();

// The `npf convert` settings of a material: the preset's (for a source that is isotropic or
// not, after `isotropy`), then every other setting over it, as `npf convert` applies its flags.
// Throws npf::Error naming the setting's origin.
ConvertSettings resolve_convert_settings(const Settings& settings, bool source_isotropic);

struct RenderCheck {
    bool enabled = false;
    std::size_t size = 64;
    std::uint32_t spp = 16;
    std::uint64_t seed = 0;
    unsigned threads = 0;
    std::string env;  // empty: the shipped environment map
};
RenderCheck resolve_render_check(const Settings& settings);

// The settings that decide the output file's contents, one "name=value" per line in name order:
// everything but threads (the thread count changes only the rounding of the fit's sums, not what
// is fitted; outputs are bit-identical for a fixed count, so configurations that compare bytes
// set it), edit (hashed by content instead) and render.* (the renders carry their own hash).
std::string canonical_settings(const Settings& settings);

struct MaterialJob {
    std::string name;    // unique key: the input's file name without its extension
    std::string input;   // absolute path
    std::string output;  // absolute path
    Settings settings;   // defaults, then the material's own entry
    std::string origin;  // where the input was named ("config.yaml:7")
};

struct BatchConfig {
    std::string path;        // the configuration file (absolute)
    std::string base_dir;    // its folder: relative paths are taken from here
    std::string output_dir;  // absolute
    std::string naming = "{name}.exr";
    std::string summary;     // absolute path without extension; empty: <output_dir>/batch-summary
    std::vector<MaterialJob> materials;  // sorted by name; materials with skip: true left out
    std::vector<std::string> skipped_by_config;  // names with skip: true
    std::vector<std::string> warnings;           // globs that matched nothing
};

// Reads and checks a configuration. Throws npf::Error naming "file:line" and the key for YAML
// syntax errors, unknown or repeated keys, values of the wrong kind or out of range, two inputs
// with the same name, and overrides for materials that no input provides. Missing input files
// named literally are not errors here: they fail as materials when the batch runs.
BatchConfig load_batch_config(const std::string& path);
// The same from text; `source` names it in errors and `base_dir` (absolute) resolves paths.
BatchConfig parse_batch_config(const std::string& yaml, const std::string& source, const std::string& base_dir);

}  // namespace npf::batch
