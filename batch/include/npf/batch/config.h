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
//     memory_limit: 8 GiB              # each material's worker process: memory and wall time
//     time_limit: 6 h
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
// ("true"/"false") with render.size, render.spp, render.seed, render.env, render.threads, and the
// worker's limits memory_limit and time_limit (text as written: "8 GiB", "6 h", "none").
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
    // The lightings rendered, each a built-in name or a map file (render/lighting.h): render.env,
    // else the conversion's own `light` set, else the built-in set (studio, key-rim,
    // directional). The material is judged by the worst.
    std::vector<std::string> lightings;
};
RenderCheck resolve_render_check(const Settings& settings);

// The limits of the process a material is converted in (docs/batch.md "Failure isolation"): its
// address space (RLIMIT_AS) and its wall time. 0: no limit. They change whether a conversion
// finishes, never what it writes, so they stay out of the content hash.
inline constexpr std::uint64_t kDefaultMemoryLimit = std::uint64_t(16) << 30;  // 16 GiB
inline constexpr double kDefaultTimeLimit = 6 * 3600.0;                         // 6 h
struct MaterialLimits {
    std::uint64_t memory_bytes = kDefaultMemoryLimit;
    double seconds = kDefaultTimeLimit;
};
MaterialLimits resolve_limits(const Settings& settings);
// "8 GiB", "512M", "1.5 GiB", "none" (K, M, G, T: powers of 1024, with or without "iB"/"B"); at
// least 64 MiB. Throws npf::Error naming `what`.
std::uint64_t parse_memory_limit(const std::string& text, const std::string& what);
// Seconds: "3600", "90 s", "30 min", "6 h", "none"; above 0. Throws npf::Error naming `what`.
double parse_time_limit(const std::string& text, const std::string& what);
// "16 GiB", "1.5 GiB", "512 MiB"; "none" for 0.
std::string describe_memory(std::uint64_t bytes);
// "3600 s", "2.5 s"; "none" for 0.
std::string describe_seconds(double seconds);

// The settings that decide the output file's contents, one "name=value" per line in name order:
// everything but threads (the fit is the same to the bit on any thread count:
// Awls.TheFitDoesNotDependOnTheThreadCount, docs/batch.md), memory_limit and time_limit (they decide whether a conversion ends, not what it
// writes), edit (hashed by content instead) and render.* (the renders carry their own hash).
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
    std::vector<std::string> warnings;           // globs that matched nothing (or only the batch's own files)
    // Glob matches left out because the batch writes them (docs/batch.md "Inputs never include
    // the batch's own files"): outputs, its work folder, renders, summaries, the configuration.
    std::vector<std::string> excluded;
};

// Whether `path` is a file this batch writes or owns, which no input may be: a file in output_dir
// whose name fits `naming` (an output, of any name), anything under <output_dir>/.npf-batch/
// (temporaries, locks) or <output_dir>/renders/, the summaries (<summary base>.json/.md and the
// shards' <base>.shard-K-of-N.json/.md), any file that is an npf batch summary by its first
// bytes, and the configuration file itself. Paths are compared after resolving symbolic links.
// Returns what it is ("an output", ...) or "" when it is none of them.
std::string batch_file_kind(const BatchConfig& config, const std::string& path);

// Reads and checks a configuration. Throws npf::Error naming "file:line" and the key for YAML
// syntax errors, unknown or repeated keys, values of the wrong kind or out of range, two inputs
// with the same name, overrides for materials that no input provides, and a literal input that is
// one of the batch's own files (batch_file_kind). Glob matches that are the batch's own files are
// left out (`excluded`). Missing input files named literally are not errors here: they fail as
// materials when the batch runs.
BatchConfig load_batch_config(const std::string& path);
// The same from text; `source` names it in errors and `base_dir` (absolute) resolves paths.
BatchConfig parse_batch_config(const std::string& yaml, const std::string& source, const std::string& base_dir);

}  // namespace npf::batch
