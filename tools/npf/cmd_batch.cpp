// npf batch: a material library from a YAML configuration (docs/batch.md): resumable (outputs
// whose content hash matches are skipped), failure-isolated (each material converted in a worker
// process of its own, `npf batch --worker JOB`, under memory and time limits), shardable, with
// JSON and Markdown summaries; --merge joins shard summaries.
#include "command_line.h"
#include "commands.h"

#include <npf/batch/config.h>
#include <npf/batch/runner.h>
#include <npf/batch/summary.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/core/text.h>

#include <csignal>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>

#include <unistd.h>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = flag_table({
    "--shard VALUE  K/N: run only shard K of N (0-based; material i of the name-sorted list goes to shard i mod N)",
    "--summary VALUE  summary base name (writes BASE.json and BASE.md; default from the config)",
    "--force  redo every material, whatever its content hash says",
    "--threads VALUE  threads per material, overriding the configuration (changes the output's rounding)",
    "--memory-limit VALUE  SIZE: memory limit of each material's worker process, overriding the configuration (8 GiB, none)",
    "--time-limit VALUE  SECONDS: wall time limit of each material's worker process, overriding the configuration (3600, 2 h, none)",
    "--in-process  convert in this process: no worker processes, no limits (a crash ends the batch; for debuggers)",
    "--worker-executable VALUE  PROGRAM: each material's worker process runs PROGRAM batch --worker JOB instead of this "
    "npf (a wrapper, or the tests' fault-injecting worker)",
    "--check  only read and check the configuration; list the materials of the shard",
    "--merge  merge shard summaries: npf batch --merge S1.json S2.json ... [-o MERGED]",
    "-o VALUE  with --merge: base name of the merged summary (default: batch-summary beside the first)",
    "--quiet  no line per material",
});

const char* kHelp =
    "usage: npf batch CONFIG.yaml [--shard K/N] [--summary BASE] [--force] [--threads N] [--check] [--quiet]\n"
    "                 [--memory-limit SIZE] [--time-limit SECONDS] [--in-process | --worker-executable PROGRAM]\n"
    "       npf batch --merge SUMMARY.json... [-o BASE]\n\n"
    "Converts every material a YAML configuration names (inputs, defaults, per-material overrides,\n"
    "edits, validation renders; docs/batch.md, configs/batch/example.yaml). An output whose content\n"
    "hash (input bytes, resolved settings, edit recipe, npf version) matches is skipped; outputs\n"
    "appear only when complete, so an interrupted batch resumes where it stopped. A material that\n"
    "fails (even by crashing: each material is converted in a process of its own, under memory and\n"
    "time limits) is reported and the others go on. Writes BASE.json and BASE.md summaries.\n"
    "Exit status: 0 all materials converted or up to date; 4 some failed (or, merging, a shard is\n"
    "missing); 1 the batch could not run (configuration, output folder).\n\n";

// Exit status when the batch ran but some materials failed.
constexpr int kSomeFailed = 4;

// The tool named in messages about the files it owns (a link there is refused).
constexpr const char* kOwner = "npf batch";

// The signal that asked the batch to stop (SIGINT, SIGTERM, SIGHUP), 0 while none did.
volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void request_stop(int signal) { g_stop_signal = signal; }

// With worker processes, Ctrl-C, SIGTERM (Slurm's scancel, a timeout) and SIGHUP stop the batch
// cleanly: the running worker is killed, the stage folder emptied, and the batch then dies of the
// same signal (stop_by_signal). In one process a conversion cannot be cut short, so the signals
// keep their default action there.
void catch_stop_signals() {
    struct sigaction action {};
    action.sa_handler = request_stop;
    sigemptyset(&action.sa_mask);
    for (const int signal : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(signal, &action, nullptr);
}

[[noreturn]] void stop_by_signal(int signal, std::size_t done) {
    std::fprintf(stderr,
                 "npf batch: stopped by signal %d after %zu materials; the work folder is emptied, no summary written; "
                 "run the same command again to resume\n",
                 signal, done);
    std::fflush(nullptr);
    ::signal(signal, SIG_DFL);
    ::raise(signal);
    std::_Exit(128 + signal);
}

// The summary's warnings and failed materials on standard error, a line each.
void report_problems(const batch::BatchSummary& summary) {
    for (const std::string& w : summary.warnings) std::fprintf(stderr, "npf batch: warning: %s\n", printable(w).c_str());
    for (const batch::MaterialResult& m : summary.materials) {
        if (m.status == batch::MaterialStatus::Failed)
            std::fprintf(stderr, "npf batch: failed: %s: %s\n", printable(m.name).c_str(), printable(m.reason).c_str());
    }
}

int run_merge(const CommandLine& cl) {
    cl.expect_positional(1, SIZE_MAX, "one or more summary files (.json) with --merge");
    // A shard that died before writing its summary must not stop the others' merge: its file is
    // reported missing (and the merge's status says the result is incomplete).
    std::vector<batch::BatchSummary> parts;
    std::vector<std::string> unreadable;
    for (const std::string& p : cl.positional()) {
        try {
            parts.push_back(batch::read_summary_json(p));
        } catch (const Error& e) {
            unreadable.push_back(e.what());
        }
    }
    if (parts.empty()) throw Error("--merge", "no summary could be read: " + unreadable.front());
    batch::BatchSummary merged = batch::merge_summaries(parts);
    for (const std::string& u : unreadable) merged.warnings.push_back("summary not merged: " + u);
    std::string base = cl.value("-o");
    // A name of npf's own choice, beside the first summary: a link there is refused.
    const bool own_name = base.empty();
    if (own_name) base = (std::filesystem::path(cl.positional().front()).parent_path() / "batch-summary").string();
    if (base.size() > 5 && base.compare(base.size() - 5, 5, ".json") == 0) base.resize(base.size() - 5);
    batch::write_summary(merged, base, own_name ? kOwner : "");
    const std::string shown = printable(base);
    std::printf("merged %zu summaries: %zu materials, %zu converted, %zu skipped, %zu failed -> %s.json, %s.md\n", parts.size(),
                merged.materials.size(), merged.count(batch::MaterialStatus::Converted),
                merged.count(batch::MaterialStatus::Skipped), merged.count(batch::MaterialStatus::Failed), shown.c_str(),
                shown.c_str());
    report_problems(merged);
    const bool complete = merged.shards.size() == std::size_t(merged.shard_count) && merged.materials.size() >= merged.config_materials;
    return merged.ok() && complete && unreadable.empty() ? 0 : kSomeFailed;
}

// --check: the shard's materials, the summary's name and the limits; nothing is made.
void print_check(const batch::BatchConfig& config, const batch::BatchOptions& options, const std::string& base) {
    const std::vector<std::size_t> members = batch::shard_members(config.materials.size(), options.shard);
    std::printf("%s: %zu materials, %zu in shard %d/%d, output folder %s\n", printable(config.path).c_str(), config.materials.size(),
                members.size(), options.shard.index, options.shard.count, printable(config.output_dir).c_str());
    for (std::size_t i : members) {
        const batch::MaterialJob& m = config.materials[i];
        std::printf("  %s: %s -> %s\n", printable(m.name).c_str(), printable(m.input).c_str(), printable(m.output).c_str());
    }
    for (const std::string& s : config.skipped_by_config) std::printf("  %s: skip (configuration)\n", printable(s).c_str());
    if (!config.excluded.empty())
        std::printf("  (%zu files matched by inputs left out: the batch writes them)\n", config.excluded.size());
    std::printf("summary %s.json, %s.md\n", printable(base).c_str(), printable(base).c_str());
    if (options.worker_executable.empty()) {
        std::printf("materials converted in this process (--in-process): no isolation, no limits\n");
        return;
    }
    // Materials by their limits: one line when all share them.
    std::map<std::string, std::string> by_limits;
    for (std::size_t i : members) {
        batch::MaterialJob m = config.materials[i];
        if (!options.memory_limit.empty()) m.settings["memory_limit"] = {options.memory_limit, "--memory-limit"};
        if (!options.time_limit.empty()) m.settings["time_limit"] = {options.time_limit, "--time-limit"};
        const batch::MaterialLimits l = batch::resolve_limits(m.settings);
        std::string& names = by_limits["memory " + batch::describe_memory(l.memory_bytes) + ", time " + batch::describe_seconds(l.seconds)];
        names += (names.empty() ? "" : ", ") + printable(m.name);
    }
    std::printf("each material in a worker process of its own, with limits\n");
    for (const auto& [limits, names] : by_limits) {
        if (by_limits.size() == 1) std::printf("  %s\n", limits.c_str());
        else std::printf("  %s: %s\n", limits.c_str(), names.c_str());
    }
}

}  // namespace

int run_batch(const std::vector<std::string>& args) {
    // The worker that converts one material for a running batch (hidden: not for people).
    if (!args.empty() && args[0] == "--worker") {
        if (args.size() != 2) throw Error("--worker", "expects one job file");
        return batch::run_batch_worker(args[1]);
    }
    const CommandLine cl = read_command_line(kHelp, kFlags, args);
    if (!cl.has("--merge")) cl.expect_positional(1, 1, "one CONFIG.yaml");
    if (cl.has("--merge")) return run_merge(cl);

    const batch::BatchConfig config = batch::load_batch_config(cl.positional()[0]);
    batch::BatchOptions options;
    if (cl.has("--shard")) options.shard = batch::parse_shard(cl.value("--shard"));
    options.force = cl.has("--force");
    options.threads = int(cl.whole("--threads", 1, 1024, std::uint64_t(options.threads)));
    if (cl.has("--memory-limit")) {
        options.memory_limit = cl.value("--memory-limit");
        batch::parse_memory_limit(options.memory_limit, "--memory-limit");
    }
    if (cl.has("--time-limit")) {
        options.time_limit = cl.value("--time-limit");
        batch::parse_time_limit(options.time_limit, "--time-limit");
    }
    // This very executable (its inode, even if the file is replaced while the batch runs).
    if (!cl.has("--in-process") && ::access("/proc/self/exe", X_OK) == 0) options.worker_executable = "/proc/self/exe";
    if (cl.has("--worker-executable")) {
        if (cl.has("--in-process")) throw Error("--worker-executable", "give --worker-executable or --in-process, not both");
        options.worker_executable = cl.value("--worker-executable");
        // Checked before anything runs: otherwise every material would fail alike.
        std::error_code ec;
        if (!std::filesystem::is_regular_file(options.worker_executable, ec) ||
            ::access(options.worker_executable.c_str(), X_OK) != 0)
            throw Error(options.worker_executable, "not an executable file (--worker-executable)");
    }
    const std::string base = cl.has("--summary") ? cl.value("--summary") : batch::summary_base(config, options.shard);
    const std::string summary_folder = std::filesystem::path(base).parent_path().string();
    // Checked (--check) or created before anything is converted: a summary that cannot be
    // written must not be found out after hours of work.
    batch::prepare_folder(config.output_dir, "output folder", false);
    batch::prepare_folder(summary_folder.empty() ? "." : summary_folder, "summary folder (" + base + ".json)", !cl.has("--check"));
    // Outputs against each other and the inputs, by identity (links and hard links count).
    batch::check_batch_files(config, base);
    for (const std::string& w : config.warnings) std::fprintf(stderr, "npf batch: warning: %s\n", printable(w).c_str());
    if (cl.has("--check")) {
        print_check(config, options, base);
        return 0;
    }
    // The default summary is a name of the batch's own choosing in its output folder: a link there
    // is refused. One the user named (`summary:`, --summary) is followed, as -o is. Either is
    // checked now, not after hours of work.
    const std::string summary_owner = cl.has("--summary") || !config.summary.empty() ? "" : kOwner;
    for (const char* ext : {".json", ".md"}) check_output_path(base + ext, OutputOptions{summary_owner, ""});
    const bool quiet = cl.has("--quiet");
    options.log = [quiet](const std::string& line) {
        if (!quiet) {
            std::printf("%s\n", line.c_str());
            std::fflush(stdout);
        }
    };
    if (!options.worker_executable.empty()) {
        catch_stop_signals();
        options.stop = &g_stop_signal;
    }
    const batch::BatchSummary summary = batch::run_batch(config, options);
    if (summary.stopped_by > 0) stop_by_signal(summary.stopped_by, summary.materials.size());
    batch::write_summary(summary, base, summary_owner);
    const std::string shown = printable(base);
    std::printf("%zu materials: %zu converted, %zu skipped, %zu failed in %.2f s; summary %s.json, %s.md\n",
                summary.materials.size(), summary.count(batch::MaterialStatus::Converted),
                summary.count(batch::MaterialStatus::Skipped), summary.count(batch::MaterialStatus::Failed), summary.seconds,
                shown.c_str(), shown.c_str());
    for (const batch::MaterialResult& m : summary.materials) {
        if (m.status == batch::MaterialStatus::Failed)
            std::fprintf(stderr, "npf batch: failed: %s: %s\n", printable(m.name).c_str(), printable(m.reason).c_str());
    }
    return summary.ok() ? 0 : kSomeFailed;
}

}  // namespace npf::cli
