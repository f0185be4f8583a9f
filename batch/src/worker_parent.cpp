#include "worker_parent.h"

#include "material_context.h"
#include "validation_renders.h"
#include "worker_job.h"
#include "worker_process.h"

#include <npf/core/error.h>
#include <npf/core/text_input.h>

#include <yaml-cpp/yaml.h>

#include <csignal>
#include <string>
#include <tuple>
#include <vector>

#include <unistd.h>

namespace npf::batch::detail {

namespace {

// Why a worker that did not answer ended, as a material's failure: "PATH: killed by signal 11
// (segmentation fault) (its last words: ...)".
std::string worker_failure(const MaterialJob& job, const WorkerEnd& end, const MaterialLimits& limits,
                           const std::string& executable, const std::string& tail) {
    const std::string said = tail.empty() ? "" : " (its last words: " + tail + ")";
    if (!end.start_error.empty()) return "cannot start the worker process " + executable + ": " + end.start_error;
    if (end.timed_out) return job.input + ": took longer than " + describe_seconds(limits.seconds) + " (time_limit), stopped";
    if (end.signal > 0) {
        if (tail.find("bad_alloc") != std::string::npos)
            return job.input + ": ran out of memory (" + memory_note(limits.memory_bytes) + "), " + signal_text(end.signal);
        std::string reason = job.input + ": killed by " + signal_text(end.signal);
        if (end.signal == SIGKILL)
            reason += " from outside, at " + describe_memory(std::uint64_t(end.peak_resident_bytes)) +
                      " resident (the system's out-of-memory killer?)";
        return reason + said;
    }
    if (end.exited && end.exit_code != 0)
        return job.input + ": the worker process exited with status " + std::to_string(end.exit_code) + said;
    return "";
}

// The worker's answer and the files it finished, read from the stage (never through a link) and
// published; a list naming anything but this material's output and renders is refused.
MaterialResult take_answer(const MaterialJob& job, BatchFolders& folders, const std::string& result, const std::string& moves) {
    const OwnedFolder& stage = folders.stage();
    const BatchSummary answer =
        parse_summary_json(stage.read_text(result, "a batch worker's answer", kConfigTextBounds), stage.path_of(result));
    const YAML::Node list = YAML::Load(stage.read_text(moves, "a batch worker's list of finished files", kConfigTextBounds));
    std::vector<std::tuple<std::string, std::string, bool>> to_move;  // staged name, final, a render
    for (const YAML::Node& m : list) {
        const std::string name = m[0].as<std::string>(), to = m[1].as<std::string>();
        const RenderCheck check = resolve_render_check(job.settings);
        bool render = false;
        for (const std::string& l : check.lightings)
            render = render || to == render_file(job, l, "reference") || to == render_file(job, l, "npf");
        if ((to != job.output && !render) || name.empty() || name.find('/') != std::string::npos)
            throw Error(stage.path_of(moves), "lists a file that is not one of this material's: " + name + " -> " + to);
        to_move.emplace_back(name, to, render);
    }
    if (answer.materials.size() != 1 || answer.materials[0].name != job.name)
        throw Error(stage.path_of(result), "the worker process answered for another material");
    MaterialResult r = answer.materials[0];
    try {
        for (const auto& [name, to, render] : to_move) publish_finished(folders, name, to, render);
    } catch (const Error& e) {
        r.status = MaterialStatus::Failed;
        r.reason = e.what();
    }
    return r;
}

}  // namespace

std::optional<MaterialResult> run_in_worker(const MaterialJob& job, BatchFolders& folders, const BatchOptions& options) {
    const int shard = options.shard.index;
    MaterialResult failed = result_for(job, shard);
    failed.status = MaterialStatus::Failed;
    MaterialLimits limits;
    try {
        limits = resolve_limits(job.settings);
    } catch (const Error& e) {
        failed.reason = e.what();
        return failed;
    }
    if (!options.force) {
        if (std::optional<MaterialResult> skipped = up_to_date_result(job, shard)) return *skipped;
    }
    const OwnedFolder& stage = folders.stage();
    MaterialContext ctx;
    ctx.stage = &stage;
    ctx.force = options.force;
    ctx.shard = shard;
    ctx.memory_limit = limits.memory_bytes;
    const std::string job_file = job.name + ".job.yaml", result = job.name + ".result.json", moves = job.name + ".moves.yaml";
    int log = -1;
    try {
        stage.write_new_file(job_file, job_text(job, ctx, result, moves));
        log = stage.create_file(job.name + ".worker.log", 0644);
    } catch (const Error& e) {
        failed.reason = e.what();
        return failed;
    }
    // The worker is told the job's path as people read it; it checks that the folder it finds
    // there is this one (device and inode in the job).
    const WorkerEnd end = run_worker_process(options.worker_executable, {"batch", "--worker", stage.path_of(job_file)},
                                          log, limits.seconds, options.stop);
    const std::string tail = last_line(log);
    ::close(log);
    if (end.stopped || (options.stop && *options.stop)) return std::nullopt;
    failed.reason = worker_failure(job, end, limits, options.worker_executable, tail);
    if (!failed.reason.empty()) return failed;
    // Ended normally (or its status was lost): its answer, and the files it finished.
    try {
        return take_answer(job, folders, result, moves);
    } catch (const std::exception& e) {
        const std::string said = tail.empty() ? "" : " (its last words: " + tail + ")";
        failed.reason = job.input + ": the worker process ended without an answer (" + std::string(e.what()) + ")" + said;
        return failed;
    }
}

}  // namespace npf::batch::detail
