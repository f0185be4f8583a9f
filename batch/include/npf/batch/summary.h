// What a batch did, per material, as JSON (for pipelines) and Markdown (for people), and the
// merge of shard summaries into one (docs/batch.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace npf::batch {

enum class MaterialStatus { Converted, Skipped, Failed };
const char* status_name(MaterialStatus status);  // "converted", "skipped", "failed"

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
    // Validation render of the output against one of the input (render: true), paired, and the
    // PSNR's paired noise floor (the same pair at the next seed).
    std::optional<double> psnr, ssim, relmse, psnr_floor;
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

    std::size_t count(MaterialStatus s) const;
    bool ok() const { return count(MaterialStatus::Failed) == 0; }
};

std::string summary_json(const BatchSummary& summary);
std::string summary_markdown(const BatchSummary& summary);
// Writes `<base>.json` and `<base>.md`, each atomically. Throws npf::Error.
void write_summary(const BatchSummary& summary, const std::string& base);

// Reads a summary written by summary_json. Throws npf::Error naming the file.
BatchSummary read_summary_json(const std::string& path);
// One summary of several shards' summaries: materials of all, by name. Warns (in `warnings`)
// about shards missing, given twice, of other shard counts or other configurations, and about a
// material reported by two shards (the later one is kept). Throws npf::Error when `parts` is empty.
BatchSummary merge_summaries(const std::vector<BatchSummary>& parts);

}  // namespace npf::batch
