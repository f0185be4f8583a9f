// run_batch: the shard's materials one after another, each in a worker process or in this one,
// with a progress line each (docs/batch.md).
#include <npf/batch/runner.h>

#include "batch_folders.h"
#include "figure_text.h"
#include "material_context.h"
#include "worker_parent.h"

#include <npf/core/text.h>

#include <chrono>
#include <cmath>

namespace npf::batch {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// "[2/7] felt: converted in 1.2 s, 0.007 MB (1/161.9), error 3.1 %, PSNR ...", one line whatever
// the names hold.
std::string progress_line(const std::string& counter, const MaterialResult& r) {
    using detail::decibels;
    using detail::fixed;
    std::string line = counter + ": " + status_name(r.status);
    if (r.status == MaterialStatus::Failed) return printable(line + ": " + r.reason);
    line += " in " + fixed(r.seconds, 2) + " s";
    if (r.output_bytes) line += ", " + detail::megabytes(r.output_bytes) + " MB";
    if (r.ratio()) line += " (1/" + fixed(*r.ratio(), 1) + ")";
    if (r.error_mean) line += ", error " + fixed(100.0 * *r.error_mean, 2) + " %";
    // "PSNR 47.10 dB, the worst of studio 55.02 (floor 63.10), key-rim 50.21 (floor 64.02), directional 47.10"
    if (r.psnr) {
        line += ", PSNR " + decibels(*r.psnr) + " dB";
        std::string each;
        for (const LightingCheck& c : r.lightings) {
            each += (each.empty() ? "" : ", ") + c.lighting + " " + decibels(c.psnr);
            if (std::isfinite(c.psnr_floor)) each += " (floor " + decibels(c.psnr_floor) + ")";
        }
        if (r.lightings.size() > 1) line += ", the worst of " + each;
        else if (r.psnr_floor) line += " (noise floor " + decibels(*r.psnr_floor) + " dB)";
    }
    if (!r.reason.empty()) line += " (" + r.reason + ")";
    return printable(line);
}

// The job with the run's overrides of every material's settings.
MaterialJob with_overrides(MaterialJob job, const BatchOptions& options) {
    if (options.threads > 0) job.settings["threads"] = {std::to_string(options.threads), "--threads"};
    if (!options.memory_limit.empty()) job.settings["memory_limit"] = {options.memory_limit, "--memory-limit"};
    if (!options.time_limit.empty()) job.settings["time_limit"] = {options.time_limit, "--time-limit"};
    return job;
}

}  // namespace

BatchSummary run_batch(const BatchConfig& config, const BatchOptions& options) {
    const auto start = Clock::now();
    const auto stopped = [&options] { return options.stop && *options.stop != 0; };
    BatchSummary summary;
    summary.config = config.path;
    summary.shard_index = options.shard.index;
    summary.shard_count = options.shard.count;
    summary.shards = {options.shard.index};
    summary.config_materials = config.materials.size();
    summary.warnings = config.warnings;

    check_batch_files(config, "");
    detail::BatchFolders folders(config.output_dir, options.shard);
    const std::vector<std::size_t> members = shard_members(config.materials.size(), options.shard);
    for (std::size_t index : members) {
        if (resolve_render_check(config.materials[index].settings).enabled) {
            folders.check_renders();
            break;
        }
    }

    detail::MaterialContext here;  // in-process: no worker executable
    here.stage = &folders.stage();
    here.folders = &folders;
    here.force = options.force;
    here.shard = options.shard.index;
    here.before_material = options.before_material;
    std::size_t done = 0;
    for (std::size_t index : members) {
        if (stopped()) break;
        const MaterialJob job = with_overrides(config.materials[index], options);
        const auto t0 = Clock::now();
        const std::string counter = "[" + std::to_string(++done) + "/" + std::to_string(members.size()) + "] " + job.name;
        std::optional<MaterialResult> r = options.worker_executable.empty() ? detail::process_material(job, here)
                                                                            : detail::run_in_worker(job, folders, options);
        folders.stage().clear();
        if (!r) break;  // stopped while its worker ran
        r->seconds = seconds_since(t0);
        if (options.log) options.log(progress_line(counter, *r));
        summary.materials.push_back(std::move(*r));
    }
    if (stopped()) summary.stopped_by = int(*options.stop);
    summary.seconds = seconds_since(start);
    return summary;
}

}  // namespace npf::batch
