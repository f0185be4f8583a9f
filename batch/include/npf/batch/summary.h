// What a batch did, per material, as JSON (for pipelines) and Markdown (for people), and the
// merge of shard summaries into one (docs/batch.md).
#pragma once

#include <npf/core/text_input.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace npf::batch {

enum class MaterialStatus { Converted, Skipped, Failed };
const char* status_name(MaterialStatus status);  // "converted", "skipped", "failed"

// One lighting's validation render pair: the paired PSNR, its noise floor (the same pair at the
// next seed; +infinity for "directional", which has no Monte Carlo), SSIM and relative MSE.
struct LightingCheck {
    std::string lighting;  // render::Lighting::label()
    double psnr = 0.0, psnr_floor = 0.0, ssim = 0.0, relmse = 0.0;
};

struct MaterialResult {
    std::string name, input, output;
    MaterialStatus status = MaterialStatus::Failed;
    std::string reason;        // failed: what went wrong (the error message)
    std::string hash;          // the content hash (empty when it could not be computed)
    int shard = 0;             // the shard that handled it
    double seconds = 0.0;      // wall time spent on this material in this run
    std::uint64_t input_bytes = 0, output_bytes = 0;
    // BRDF-space relative RMS error of the file (mean over channels, worst channel) and of the
    // fitted factors before compression, when measured.
    std::optional<double> error_mean, error_max, fitted_error_mean, fitted_error_max;
    // The largest directional albedo of the output (npf convert's energy check); above 1 the
    // conversion reflects more light than it receives somewhere.
    std::optional<double> albedo_max;
    // Validation renders of the output against the input (render: true), paired, under each
    // lighting of the set (render.env), in the set's order ...
    std::vector<LightingCheck> lightings;
    // ... and the worst lighting's figures (the lowest PSNR): what a material is judged by.
    std::optional<double> psnr, ssim, relmse, psnr_floor;
    // Sets psnr, ssim, relmse and psnr_floor from `lightings` (nothing when it is empty).
    void judge_by_worst_lighting();
    std::vector<std::string> edits;  // edit history entries the batch added
    // input_bytes / output_bytes (how many times smaller the output is), when both are known.
    std::optional<double> ratio() const;
};

struct BatchSummary {
    std::string config;           // the configuration file
    int shard_index = 0, shard_count = 1;
    std::vector<int> shards;      // the shards this summary covers (one, or the merged ones)
    std::size_t config_materials = 0;  // materials in the whole configuration (every shard)
    double seconds = 0.0;         // wall time (merged: the sum over shards)
    std::vector<MaterialResult> materials;  // by name
    std::vector<std::string> warnings;
    int stopped_by = 0;  // > 0: the run was stopped by this signal (not written in the summary)

    std::size_t count(MaterialStatus s) const;
    bool ok() const { return count(MaterialStatus::Failed) == 0; }
};

// Valid JSON whatever the names and messages hold (control characters escaped).
std::string summary_json(const BatchSummary& summary);
// Names and messages with their control characters escaped (npf::printable): one line each.
std::string summary_markdown(const BatchSummary& summary);
// Writes `<base>.json` and `<base>.md`, each atomically. `owned_by` non-empty ("npf batch"): the
// names are the tool's own choice (the default summary in the output folder), so that a link at
// them is refused rather than followed (OutputOptions::owned_by). Throws npf::Error.
void write_summary(const BatchSummary& summary, const std::string& base, const std::string& owned_by = "");

// The bounds of a summary read back (--merge, a worker's answer): a line per material of about
// 700 bytes, so 256 MiB holds a merged library of 300,000 materials.
inline constexpr TextBounds kSummaryTextBounds{std::uint64_t(256) << 20, std::size_t(1) << 20};
// Reads a summary written by summary_json, within kSummaryTextBounds. Throws npf::Error naming
// the file.
BatchSummary read_summary_json(const std::string& path);
// The same from its text; `source` names it in errors.
BatchSummary parse_summary_json(const std::string& text, const std::string& source);
// One summary of several shards' summaries: materials of all, by name. Warns (in `warnings`)
// about shards missing, given twice, of other shard counts or other configurations, and about a
// material reported by two shards (the later one is kept). Throws npf::Error when `parts` is empty.
BatchSummary merge_summaries(const std::vector<BatchSummary>& parts);

}  // namespace npf::batch
