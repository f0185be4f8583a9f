// `npf batch` against a hostile file system (issue 33, docs/reliability.md sec. 3): links planted
// at the places the batch owns (its work folder, shard folder, lock, renders, default summary)
// are refused with a line naming them, and nothing outside the output folder changes; a worker
// or the batch itself killed or terminated mid-material leaves nothing behind and the next run
// resumes to the same bytes; two batches over one output folder; read-only folders; a glob that
// meets a FIFO, a socket, a device or a dangling link says so; control characters in file names
// never split a line; text inputs are bounded; an output that is an input (through a link or a
// hard link) or another output is refused before any work.
#include "batch_runs.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/batch/summary.h>

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <grp.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
namespace batch = npf::batch;
using npf::testing::contains;
using npf::testing::describe;
using npf::testing::read_text;
using npf::testing::ToolRun;
using npf::testing::write_batch_config;
using npf::testing::write_text;

void write_material(const std::string& path, float alpha) {
    npf::testing::SyntheticRglSpec s;
    s.theta_count = 5;
    s.ndf_size = 16;
    s.vndf_size = 8;
    s.data_size = 8;
    s.alpha_x = s.alpha_y = alpha;
    npf::testing::write_synthetic_rgl(s, path);
}

// A folder with the named materials in `in/`.
std::string library(const std::string& tag, const std::vector<std::string>& names) {
    const std::string dir = npf::testing::temporary_folder(tag);
    fs::create_directories(dir + "/in");
    for (std::size_t i = 0; i < names.size(); ++i) write_material(dir + "/in/" + names[i] + ".bsdf", 0.2f + 0.1f * float(i));
    return dir;
}

// Every entry under `dir` that is not under `skip` (a path relative to it), by kind and content:
// links are listed, never followed.
std::map<std::string, std::string> tree_of(const std::string& dir, const std::string& skip = "") {
    std::map<std::string, std::string> tree;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator(); it.increment(ec)) {
        const std::string rel = fs::relative(it->path(), dir, ec).string();
        if (!skip.empty() && (rel == skip || rel.rfind(skip + "/", 0) == 0)) {
            if (it->is_directory(ec) && !it->is_symlink(ec)) it.disable_recursion_pending();
            continue;
        }
        const fs::file_status st = it->symlink_status(ec);
        if (st.type() == fs::file_type::symlink) tree[rel] = "link to " + fs::read_symlink(it->path(), ec).string();
        else if (st.type() == fs::file_type::directory) tree[rel] = "folder";
        else if (st.type() == fs::file_type::regular) tree[rel] = "file of hash " + std::to_string(std::hash<std::string>()(read_text(it->path().string())));
        else tree[rel] = "special";
    }
    return tree;
}

// A victim tree outside the output folder: files and a folder with a file.
void write_victim(const std::string& victim) {
    fs::create_directories(victim + "/sub");
    write_text(victim + "/precious.txt", "keep me");
    write_text(victim + "/sub/deeper.txt", "keep me too");
}

struct RunOptions {
    std::vector<std::string> env;     // NAME=VALUE, for this run only
    bool unprivileged = false;         // as nobody when root (who writes anywhere)
    double deadline_s = 120;           // then killed
    std::uint64_t memory_cap = 0;      // RLIMIT_AS, bytes; 0: none
};

// `npf args...` started in the background, its output into `log` + ".out" / ".err".
pid_t start_tool(const std::vector<std::string>& args, const std::string& log, const RunOptions& o = {}) {
    const pid_t pid = ::fork();
    if (pid != 0) return pid;
    for (const std::string& e : o.env) ::putenv(const_cast<char*>(e.c_str()));
    const int out = ::open((log + ".out").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
    const int err = ::open((log + ".err").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (out < 0 || err < 0) ::_exit(126);
    ::dup2(out, 1), ::dup2(err, 2);
    if (o.unprivileged && ::geteuid() == 0 && (::setgroups(0, nullptr) != 0 || ::setgid(65534) != 0 || ::setuid(65534) != 0))
        ::_exit(125);
    if (o.memory_cap > 0) {
        const struct rlimit cap {rlim_t(o.memory_cap), rlim_t(o.memory_cap)};
        ::setrlimit(RLIMIT_AS, &cap);
    }
    std::vector<std::string> copy = {NPF_TOOL_PATH};
    copy.insert(copy.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(NPF_TOOL_PATH, argv.data());
    ::_exit(127);
}

// Waits for `pid` at most `deadline_s` (then kills it); its wait status, or -1 when it was killed
// at the deadline.
int wait_for(pid_t pid, double deadline_s) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(deadline_s);
    int status = 0;
    while (::waitpid(pid, &status, WNOHANG) == 0) {
        if (std::chrono::steady_clock::now() > end) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &status, 0);
            return -1;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return status;
}

// `npf args...` run to its end (or its deadline).
ToolRun run(const std::vector<std::string>& args, const RunOptions& o = {}) {
    static int counter = 0;
    const std::string log = npf::testing::temporary_folder("batch-hostile-log") + "/run" + std::to_string(++counter);
    ToolRun r;
    r.command = "npf";
    for (const std::string& a : args) r.command += " " + npf::testing::shell_quote(a);
    const int status = wait_for(start_tool(args, log, o), o.deadline_s);
    r.status = status >= 0 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_text(log + ".out");
    r.err = read_text(log + ".err") + (status < 0 ? "\n(killed at the test's deadline)" : "");
    return r;
}

// The pid of a live (not zombie) process whose command line holds `part`; 0 when none.
pid_t process_with(const std::string& part) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator("/proc", ec)) {
        const std::string pid = e.path().filename().string();
        if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
        std::string cmdline = read_text(e.path().string() + "/cmdline");
        for (char& c : cmdline) c = c == '\0' ? ' ' : c;
        if (!contains(cmdline, part)) continue;
        const std::string stat = read_text(e.path().string() + "/stat");
        const std::size_t close = stat.rfind(')');
        if (close != std::string::npos && close + 2 < stat.size() && stat[close + 2] == 'Z') continue;
        return pid_t(std::atol(pid.c_str()));
    }
    return 0;
}

// Waits (at most 30 s) for the worker of material `name` of the shard-0-of-1 stage under `out`.
pid_t wait_for_worker(const std::string& out, const std::string& name) {
    const std::string part = "--worker " + out + "/.npf-batch/shard-0-of-1/" + name + ".job.yaml";
    for (int i = 0; i < 6000; ++i) {
        if (const pid_t pid = process_with(part)) return pid;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return 0;
}

std::map<std::string, std::string> statuses(const std::string& summary) {
    std::map<std::string, std::string> out;
    for (const batch::MaterialResult& m : batch::read_summary_json(summary).materials) out[m.name] = batch::status_name(m.status);
    return out;
}

std::string reason_of(const std::string& summary, const std::string& name) {
    for (const batch::MaterialResult& m : batch::read_summary_json(summary).materials)
        if (m.name == name) return m.reason;
    return "(not in the summary)";
}

bool has_temporaries(const std::string& dir) {
    for (const auto& [rel, kind] : tree_of(dir))
        if (contains(rel, ".tmp-")) return true;
    return false;
}

// ---- 1. The batch's own places never follow links ----------------------------------------------

// The reviewed case: a link at the shard folder made every file and folder in its target go
// (clear_folder iterated through it) and exit 0. Now it is refused, and nothing outside the
// output folder changes.
TEST(BatchHostile, ALinkAtTheShardFolderIsRefusedAndNothingOutsideChanges) {
    const std::string dir = library("batch-hostile-shard-link", {"glossy"});
    write_victim(dir + "/victim");
    fs::create_directories(dir + "/out/.npf-batch");
    fs::create_directory_symlink("../../victim", dir + "/out/.npf-batch/shard-0-of-1");
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out");
    const auto before = tree_of(dir, "out");
    const ToolRun r = run({"batch", cfg});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "npf batch: error: " + dir +
                                    "/out/.npf-batch/shard-0-of-1: is a symbolic link (to ../../victim): a folder npf batch owns "
                                    "is never followed; remove it\n"))
        << describe(r);
    EXPECT_EQ(tree_of(dir, "out"), before) << "something outside the output folder changed";
    EXPECT_FALSE(fs::exists(dir + "/out/glossy.exr")) << "converted although the batch could not run safely";
}

// A link at `.npf-batch` itself: the shard folder in its target was emptied, its lock made there.
TEST(BatchHostile, ALinkAtTheWorkFolderIsRefused) {
    const std::string dir = library("batch-hostile-work-link", {"glossy"});
    write_victim(dir + "/victim/shard-0-of-1");
    fs::create_directories(dir + "/out");
    fs::create_directory_symlink("../victim", dir + "/out/.npf-batch");
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out");
    const auto before = tree_of(dir, "out");
    const ToolRun r = run({"batch", cfg});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, dir + "/out/.npf-batch: is a symbolic link (to ../victim): a folder npf batch owns is never followed; remove it"))
        << describe(r);
    EXPECT_EQ(tree_of(dir, "out"), before);
}

// A link at the lock file: opened with O_CREAT through it, it made a file wherever it pointed.
TEST(BatchHostile, ALinkAtTheLockIsRefused) {
    const std::string dir = library("batch-hostile-lock-link", {"glossy"});
    write_victim(dir + "/victim");
    fs::create_directories(dir + "/out/.npf-batch");
    fs::create_symlink("../../victim/planted.lock", dir + "/out/.npf-batch/shard-0-of-1.lock");
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out");
    const auto before = tree_of(dir, "out");
    const ToolRun r = run({"batch", cfg});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, dir + "/out/.npf-batch/shard-0-of-1.lock: is a symbolic link (to ../../victim/planted.lock): a file "
                                      "npf batch owns is never followed; remove it"))
        << describe(r);
    EXPECT_EQ(tree_of(dir, "out"), before);
}

// One lighting: the renders' hostile names are the same under each.
const char* const kRenderSettings = "  render: {size: 16, spp: 1, threads: 1, env: studio}\n";

// A link at `renders/`: the validation renders went into its target.
TEST(BatchHostile, ALinkAtTheRendersFolderIsRefusedBeforeAnyWork) {
    const std::string dir = library("batch-hostile-renders-link", {"glossy"});
    write_victim(dir + "/victim");
    fs::create_directories(dir + "/out");
    fs::create_directory_symlink("../victim", dir + "/out/renders");
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out", kRenderSettings);
    const auto before = tree_of(dir, "out");
    const ToolRun r = run({"batch", cfg});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, dir + "/out/renders: is a symbolic link (to ../victim): a folder npf batch owns is never followed; remove it"))
        << describe(r);
    EXPECT_EQ(tree_of(dir, "out"), before);
    EXPECT_FALSE(fs::exists(dir + "/out/glossy.exr"));
}

// A link at a render's name inside `renders/`: publishing followed it and replaced its target.
// Now that material fails, naming the link; the others are unaffected.
TEST(BatchHostile, ALinkAtARenderIsRefused) {
    const std::string dir = library("batch-hostile-render-file-link", {"glossy"});
    write_victim(dir + "/victim");
    write_text(dir + "/victim/render.exr", "not a render");
    fs::create_directories(dir + "/out/renders");
    fs::create_symlink("../../victim/render.exr", dir + "/out/renders/glossy.studio.npf.exr");
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out", kRenderSettings);
    const auto before = tree_of(dir, "out");
    const ToolRun r = run({"batch", cfg});
    EXPECT_EQ(r.status, 4) << describe(r);
    EXPECT_TRUE(contains(reason_of(dir + "/out/batch-summary.json", "glossy"),
                         dir + "/out/renders/glossy.studio.npf.exr: is a symbolic link (to ../../victim/render.exr): a file npf batch "
                               "owns is never followed; remove it"))
        << describe(r);
    EXPECT_EQ(tree_of(dir, "out"), before);
    EXPECT_TRUE(fs::is_symlink(dir + "/out/renders/glossy.studio.npf.exr"));
}

// The default summary is a name of the batch's own choosing: a link there is refused before any
// work (it replaced its target after all of it).
TEST(BatchHostile, ALinkAtTheDefaultSummaryIsRefusedBeforeAnyWork) {
    const std::string dir = library("batch-hostile-summary-link", {"glossy"});
    write_victim(dir + "/victim");
    fs::create_directories(dir + "/out");
    fs::create_symlink("../victim/precious.txt", dir + "/out/batch-summary.json");
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out");
    const auto before = tree_of(dir, "out");
    const ToolRun r = run({"batch", cfg});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, dir + "/out/batch-summary.json: is a symbolic link (to ../victim/precious.txt): a file npf batch owns "
                                      "is never followed; remove it"))
        << describe(r);
    EXPECT_EQ(tree_of(dir, "out"), before);
    EXPECT_FALSE(fs::exists(dir + "/out/glossy.exr"));
}

// What the user names may be a link and is followed, as -o is: the output folder, and a summary
// named in the configuration.
TEST(BatchHostile, TheUsersOwnChoicesMayBeLinks) {
    const std::string dir = library("batch-hostile-user-links", {"glossy"});
    fs::create_directories(dir + "/real");
    fs::create_directory_symlink("real", dir + "/out");
    fs::create_directories(dir + "/sums");
    write_text(dir + "/kept.json", "the link's target before the batch");
    fs::create_symlink("../kept.json", dir + "/sums/s.json");
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out", "summary: sums/s\n");
    const ToolRun r = run({"batch", cfg});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(fs::is_regular_file(dir + "/real/glossy.exr"));
    EXPECT_TRUE(fs::is_symlink(dir + "/sums/s.json"));
    EXPECT_EQ(statuses(dir + "/kept.json"), (std::map<std::string, std::string>{{"glossy", "converted"}}));
}

// ---- 2. Killed, terminated, run twice at once, read-only ----------------------------------------

// Two materials, the second (in name order) slow enough (about a second) to be caught converting.
std::string slow_library(const std::string& tag, std::string& extra) {
    const std::string dir = library(tag, {"glossy"});
    npf::testing::SyntheticRglSpec slow;
    slow.theta_count = 5, slow.ndf_size = 16, slow.vndf_size = 8, slow.data_size = 8, slow.phi_count = 4, slow.spectral = true;
    npf::testing::write_synthetic_rgl(slow, dir + "/in/middle.bsdf");
    extra = "materials:\n  middle: {grid: [24, 32, 24, 32], g_grid: [24, 32], phi_d_samples: 8, iterations: 200, tolerance: 0}\n";
    return dir;
}

// kill -9 and SIGTERM of a worker in the middle of its material: that material fails with the
// signal, nothing of it is published, the stage is emptied, and the next run converts it to the
// bytes of an uninterrupted batch.
TEST(BatchHostile, AWorkerKilledOrTerminatedFailsItsMaterialAndTheNextRunResumes) {
    std::string extra;
    const std::string dir = slow_library("batch-hostile-worker-kill", extra);
    const std::string ref = write_batch_config(dir + "/ref.yaml", dir + "/in", dir + "/ref", extra);
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out", extra);
    ASSERT_EQ(run({"batch", ref, "--quiet"}).status, 0);
    const std::map<int, std::string> signals = {{SIGKILL, "killed by signal 9 (killed) from outside"},
                                                {SIGTERM, "killed by signal 15 (terminated)"}};
    for (const auto& [signal, reason] : signals) {
        const pid_t batch_pid = start_tool({"batch", cfg}, dir + "/run" + std::to_string(signal));
        const pid_t worker = wait_for_worker(dir + "/out", "middle");
        ASSERT_GT(worker, 0) << "the worker of 'middle' was not seen";
        std::this_thread::sleep_for(std::chrono::milliseconds(300));  // past its start-up, into the fit
        ::kill(worker, signal);
        const int status = wait_for(batch_pid, 120);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 4) << read_text(dir + "/run" + std::to_string(signal) + ".err");
        EXPECT_TRUE(contains(reason_of(dir + "/out/batch-summary.json", "middle"), reason))
            << reason_of(dir + "/out/batch-summary.json", "middle");
        EXPECT_FALSE(fs::exists(dir + "/out/middle.exr"));
        EXPECT_FALSE(has_temporaries(dir + "/out"));
        EXPECT_TRUE(npf::testing::folder_entries(dir + "/out/.npf-batch/shard-0-of-1").empty());
    }
    const ToolRun resumed = run({"batch", cfg});
    ASSERT_EQ(resumed.status, 0) << describe(resumed);
    EXPECT_EQ(statuses(dir + "/out/batch-summary.json"),
              (std::map<std::string, std::string>{{"glossy", "skipped"}, {"middle", "converted"}}));
    EXPECT_TRUE(npf::testing::exr_outputs_of(dir + "/ref") == npf::testing::exr_outputs_of(dir + "/out"));
}

// SIGTERM of the batch (Slurm's scancel, a timeout) while a worker converts: the worker is killed,
// the stage emptied, no summary written, and the batch ends by SIGTERM; it used to die leaving
// the job file and the worker's log in the stage. The next run resumes to the same bytes.
TEST(BatchHostile, SigtermOfTheBatchLeavesNothingBehindAndTheNextRunResumes) {
    const std::string dir = library("batch-hostile-sigterm", {"glossy", "stuck"});
    const std::string ref = write_batch_config(dir + "/ref.yaml", dir + "/in", dir + "/ref");
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out");
    ASSERT_EQ(run({"batch", ref, "--quiet"}).status, 0);
    RunOptions hang;
    hang.env = {"NPF_TEST_FAULT=hang:stuck"};
    const pid_t batch_pid = start_tool({"batch", cfg}, dir + "/stopped", hang);
    const pid_t worker = wait_for_worker(dir + "/out", "stuck");
    ASSERT_GT(worker, 0) << read_text(dir + "/stopped.err");
    ::kill(batch_pid, SIGTERM);
    const int status = wait_for(batch_pid, 60);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << "status " << status << "\n" << read_text(dir + "/stopped.err");
    EXPECT_TRUE(contains(read_text(dir + "/stopped.err"), "npf batch: stopped by signal 15 after 1 materials"))
        << read_text(dir + "/stopped.err");
    EXPECT_EQ(process_with("--worker " + dir + "/out/.npf-batch/shard-0-of-1/stuck.job.yaml"), 0) << "the worker outlived its batch";
    EXPECT_TRUE(npf::testing::folder_entries(dir + "/out/.npf-batch/shard-0-of-1").empty());
    EXPECT_EQ(npf::testing::folder_entries(dir + "/out"), (std::vector<std::string>{".npf-batch", "glossy.exr"}));

    const ToolRun resumed = run({"batch", cfg});
    ASSERT_EQ(resumed.status, 0) << describe(resumed);
    EXPECT_EQ(statuses(dir + "/out/batch-summary.json"),
              (std::map<std::string, std::string>{{"glossy", "skipped"}, {"stuck", "converted"}}));
    EXPECT_TRUE(npf::testing::exr_outputs_of(dir + "/ref") == npf::testing::exr_outputs_of(dir + "/out"));
}

// Two batches on one output folder at once: the same shard (of the same or of another
// configuration) is refused by its lock, naming it; other shard counts run side by side, each in
// its own stage, converting some materials twice into the same bytes.
TEST(BatchHostile, TwoBatchesOnOneOutputFolder) {
    const std::string dir = library("batch-hostile-two-batches", {"a", "b"});
    fs::create_directories(dir + "/hang");
    write_material(dir + "/hang/stuck.bsdf", 0.45f);
    const std::string ref = write_batch_config(dir + "/ref.yaml", dir + "/in", dir + "/ref");
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out");
    const std::string holding = write_batch_config(dir + "/holding.yaml", dir + "/hang", dir + "/out");
    ASSERT_EQ(run({"batch", ref, "--quiet"}).status, 0);

    RunOptions hang;
    hang.env = {"NPF_TEST_FAULT=hang:stuck"};
    const pid_t holder = start_tool({"batch", holding}, dir + "/holder", hang);
    ASSERT_GT(wait_for_worker(dir + "/out", "stuck"), 0) << read_text(dir + "/holder.err");
    const std::string held = "npf batch: error: " + dir +
                             "/out/.npf-batch/shard-0-of-1.lock: another npf batch is running this shard in this output folder "
                             "(the lock is held)";
    for (const std::string& config : {holding, cfg}) {
        const ToolRun second = run({"batch", config});
        EXPECT_EQ(second.status, 1) << describe(second);
        EXPECT_TRUE(contains(second.err, held)) << describe(second);
    }
    ::kill(holder, SIGTERM);
    wait_for(holder, 60);

    // Shards 0/1, 0/2 and 1/2 at once.
    std::vector<pid_t> runs;
    for (const char* shard : {"0/1", "0/2", "1/2"})
        runs.push_back(start_tool({"batch", cfg, "--shard", shard}, dir + "/shard" + std::to_string(runs.size())));
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const int status = wait_for(runs[i], 120);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << read_text(dir + "/shard" + std::to_string(i) + ".err");
    }
    EXPECT_TRUE(npf::testing::exr_outputs_of(dir + "/ref") == npf::testing::exr_outputs_of(dir + "/out"));
    for (const char* stage : {"shard-0-of-1", "shard-0-of-2", "shard-1-of-2"})
        EXPECT_TRUE(npf::testing::folder_entries(dir + "/out/.npf-batch/" + stage).empty()) << stage;
    EXPECT_FALSE(has_temporaries(dir + "/out"));
}

// A worker uses only the stage folder its batch made (its device and inode are in the job) and a
// job file in it: a folder put in its place, or a job from elsewhere, is refused.
TEST(BatchHostile, AWorkerUsesOnlyTheStageItsBatchMade) {
    const std::string dir = npf::testing::temporary_folder("batch-hostile-worker-stage");
    fs::create_directories(dir + "/stage");
    fs::create_directories(dir + "/elsewhere");
    struct stat stage {}, other {};
    ASSERT_EQ(::stat((dir + "/stage").c_str(), &stage), 0);
    ASSERT_EQ(::stat((dir + "/elsewhere").c_str(), &other), 0);
    const auto job = [&](const struct stat& id) {
        return "npf_batch_worker_job: 2\nparent: " + std::to_string(::getpid()) + "\nname: \"m\"\ninput: \"" + dir +
               "/m.bsdf\"\noutput: \"" + dir + "/m.exr\"\norigin: \"x\"\nstage: \"" + dir + "/stage\"\nstage_device: \"" +
               std::to_string(id.st_dev) + "\"\nstage_inode: \"" + std::to_string(id.st_ino) +
               "\"\nforce: false\nshard: 0\nmemory_limit: \"0\"\nresult: \"m.result.json\"\nmoves: \"m.moves.yaml\"\nsettings: {}\n";
    };
    write_text(dir + "/stage/m.job.yaml", job(other));
    const ToolRun swapped = run({"batch", "--worker", dir + "/stage/m.job.yaml"});
    EXPECT_EQ(swapped.status, 3) << describe(swapped);
    EXPECT_TRUE(contains(swapped.err, "npf batch --worker: " + dir + "/stage: is not the folder npf batch made (another was put in its place): not used"))
        << describe(swapped);
    write_text(dir + "/elsewhere/m.job.yaml", job(stage));
    const ToolRun foreign = run({"batch", "--worker", dir + "/elsewhere/m.job.yaml"});
    EXPECT_EQ(foreign.status, 3) << describe(foreign);
    EXPECT_TRUE(contains(foreign.err, dir + "/elsewhere/m.job.yaml: is not a job in the work folder the batch made: not used"))
        << describe(foreign);
    EXPECT_TRUE(npf::testing::folder_entries(dir + "/stage") == std::vector<std::string>{"m.job.yaml"});
}

// Runs as nobody when the tests run as root: root writes into read-only folders.
RunOptions unprivileged() {
    RunOptions o;
    o.unprivileged = true;
    return o;
}

// Whether a process of the tests can become nobody when it is root (not in a user namespace
// without that user, say); always when it is not root.
bool can_drop_privileges() {
    if (::geteuid() != 0) return true;
    const pid_t pid = ::fork();
    if (pid == 0) ::_exit(::setgroups(0, nullptr) == 0 && ::setgid(65534) == 0 && ::setuid(65534) == 0 ? 0 : 1);
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

void make_reachable(const std::string& dir) {
    if (::geteuid() == 0) fs::permissions(dir, fs::perms::all);  // nobody walks and writes it
}

// A read-only output folder, a read-only `.npf-batch` and a read-only stage holding a leftover
// fail before any work with the folder named (the stage used to be left as it was, and every
// material then failed on its job file).
TEST(BatchHostile, ReadOnlyFoldersFailBeforeAnyWork) {
    if (!can_drop_privileges()) GTEST_SKIP() << "running as root, and cannot run the tool as nobody: root writes anywhere";
    const std::string dir = library("batch-hostile-read-only", {"glossy"});
    make_reachable(dir);
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out");
    fs::create_directories(dir + "/out");
    fs::permissions(dir + "/out", fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec |
                                      fs::perms::others_read | fs::perms::others_exec);
    const ToolRun out = run({"batch", cfg}, unprivileged());
    EXPECT_EQ(out.status, 1) << describe(out);
    EXPECT_TRUE(contains(out.err, "output folder: " + dir + "/out is not writable (Permission denied)")) << describe(out);

    const fs::perms read_only = fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec |
                                fs::perms::others_read | fs::perms::others_exec;
    fs::permissions(dir + "/out", fs::perms::all);
    fs::create_directories(dir + "/out/.npf-batch");
    fs::permissions(dir + "/out/.npf-batch", read_only);
    const ToolRun work = run({"batch", cfg}, unprivileged());
    EXPECT_EQ(work.status, 1) << describe(work);
    EXPECT_TRUE(contains(work.err, dir + "/out/.npf-batch/shard-0-of-1.lock: cannot create: Permission denied")) << describe(work);

    fs::permissions(dir + "/out/.npf-batch", fs::perms::all);
    fs::create_directories(dir + "/out/.npf-batch/shard-0-of-1");
    write_text(dir + "/out/.npf-batch/shard-0-of-1/left.job.yaml", "left by a killed run");
    fs::permissions(dir + "/out/.npf-batch/shard-0-of-1", read_only);
    const ToolRun stage = run({"batch", cfg}, unprivileged());
    fs::permissions(dir + "/out/.npf-batch/shard-0-of-1", fs::perms::all);
    EXPECT_EQ(stage.status, 1) << describe(stage);
    EXPECT_TRUE(contains(stage.err, dir + "/out/.npf-batch/shard-0-of-1/left.job.yaml: cannot remove it to empty a folder npf batch "
                                        "owns: Permission denied"))
        << describe(stage);
    EXPECT_FALSE(fs::exists(dir + "/out/glossy.exr"));
}

// ---- 3. What a glob meets, names, bounded text ---------------------------------------------------

// A glob's match that is not a material file is named in a warning (stderr and the summary), no
// longer dropped silently; a FIFO named like a summary no longer hangs the batch (its first bytes
// were read to tell whether it is one: a literal input `in/stream.json` waited for a writer).
TEST(BatchHostile, AGlobNamesWhatItLeavesOut) {
    const std::string dir = library("batch-hostile-glob", {"glossy"});
    const std::string in = dir + "/in";
    ASSERT_EQ(::mkfifo((in + "/pipe.bsdf").c_str(), 0644), 0);
    ASSERT_EQ(::mkfifo((in + "/stream.json").c_str(), 0644), 0);
    fs::create_symlink("/dev/null", in + "/null.bsdf");
    fs::create_symlink("missing.bsdf", in + "/dangling.bsdf");
    const int sock = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    const std::string sock_path = in + "/sock.bsdf";
    ASSERT_LT(sock_path.size(), sizeof address.sun_path);
    sock_path.copy(address.sun_path, sock_path.size());
    ASSERT_EQ(::bind(sock, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
    const std::string cfg = dir + "/b.yaml";
    write_text(cfg, "output_dir: out\ninputs: ['in/*.bsdf', 'in/*.json']\n" + std::string(npf::testing::kBatchTestDefaults));
    RunOptions o;
    o.deadline_s = 60;
    const ToolRun r = run({"batch", cfg}, o);
    ::close(sock);
    ASSERT_EQ(r.status, 0) << describe(r);
    const std::vector<std::string> expected = {
        "b.yaml:2: 'IN/*.bsdf' matches IN/dangling.bsdf, a symbolic link to missing.bsdf, which does not exist: not a material file, left out",
        "b.yaml:2: 'IN/*.bsdf' matches IN/null.bsdf, a character device: not a material file, left out",
        "b.yaml:2: 'IN/*.bsdf' matches IN/pipe.bsdf, a FIFO (named pipe): not a material file, left out",
        "b.yaml:2: 'IN/*.bsdf' matches IN/sock.bsdf, a socket: not a material file, left out",
        "b.yaml:2: 'IN/*.json' matches IN/stream.json, a FIFO (named pipe): not a material file, left out",
    };
    const batch::BatchSummary s = batch::read_summary_json(dir + "/out/batch-summary.json");
    ASSERT_EQ(s.warnings.size(), expected.size()) << describe(r);
    for (std::size_t i = 0; i < expected.size(); ++i) {
        std::string want = expected[i];
        for (std::size_t at; (at = want.find("IN")) != std::string::npos;) want.replace(at, 2, in);
        EXPECT_TRUE(contains(s.warnings[i], want)) << s.warnings[i] << "\nwanted: " << want;
        EXPECT_TRUE(contains(r.err, "npf batch: warning: " + s.warnings[i] + "\n")) << describe(r);
    }
    EXPECT_EQ(statuses(dir + "/out/batch-summary.json"), (std::map<std::string, std::string>{{"glossy", "converted"}}));

    write_text(cfg, "output_dir: out\ninputs: [in/stream.json]\n" + std::string(npf::testing::kBatchTestDefaults));
    const ToolRun literal = run({"batch", cfg}, o);
    EXPECT_EQ(literal.status, 4) << describe(literal);
    EXPECT_TRUE(contains(literal.err, "npf batch: failed: stream: " + in + "/stream.json: not a regular file\n")) << describe(literal);
}

// A newline, a carriage return or an escape sequence in a file name no longer splits or repaints
// the progress line, the error lines or the Markdown summary; the JSON summary keeps the names
// exactly (valid JSON, escaped).
TEST(BatchHostile, ControlCharactersInNamesStayOnOneLine) {
    const std::string dir = library("batch-hostile-control", {});
    write_material(dir + "/in/new\nline.bsdf", 0.3f);
    write_material(dir + "/in/esc\x1b[31mred.bsdf", 0.4f);
    write_text(dir + "/in/bad\rname.bsdf", "not a material");
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out");
    const ToolRun r = run({"batch", cfg});
    EXPECT_EQ(r.status, 4) << describe(r);
    const std::vector<std::string> lines = npf::testing::lines_of(r.out);
    ASSERT_EQ(lines.size(), 4u) << describe(r);
    EXPECT_EQ(lines[0].rfind("[1/3] bad\\rname: failed: " + dir + "/in/bad\\rname.bsdf: ", 0), 0u) << lines[0];
    EXPECT_EQ(lines[1].rfind("[2/3] esc\\x1b[31mred: converted in ", 0), 0u) << lines[1];
    EXPECT_EQ(lines[2].rfind("[3/3] new\\nline: converted in ", 0), 0u) << lines[2];
    EXPECT_TRUE(contains(r.err, "npf batch: failed: bad\\rname: " + dir + "/in/bad\\rname.bsdf: ")) << describe(r);
    for (const std::string* text : {&r.out, &r.err}) {
        for (char c : *text) EXPECT_FALSE((c < 0x20 && c != '\n') || c == 0x7f) << "a raw control character in\n" << *text;
    }
    EXPECT_EQ(statuses(dir + "/out/batch-summary.json"),
              (std::map<std::string, std::string>{{"bad\rname", "failed"}, {"esc\x1b[31mred", "converted"}, {"new\nline", "converted"}}));
    const std::string md = read_text(dir + "/out/batch-summary.md");
    for (char c : md) EXPECT_FALSE((c < 0x20 && c != '\n') || c == 0x7f) << "a raw control character in the Markdown summary";
    EXPECT_TRUE(contains(md, "\n| new\\nline | converted | ")) << md;
    EXPECT_TRUE(contains(md, "\n| esc\\x1b[31mred | converted | ")) << md;
}

// An edit recipe that is a FIFO (or a device) fails its material at once: hashing it used to wait
// for a writer, holding a worker until its time_limit (6 h by default) and an --in-process batch
// for ever.
TEST(BatchHostile, AnEditRecipeThatIsAFifoFailsAtOnce) {
    const std::string dir = library("batch-hostile-edit-fifo", {"glossy"});
    ASSERT_EQ(::mkfifo((dir + "/pipe.yaml").c_str(), 0644), 0);
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out", "  edit: pipe.yaml\n  time_limit: 60\n");
    RunOptions o;
    o.deadline_s = 30;
    for (const std::vector<std::string>& args : {std::vector<std::string>{"batch", cfg}, std::vector<std::string>{"batch", cfg, "--in-process"}}) {
        const ToolRun r = run(args, o);
        EXPECT_EQ(r.status, 4) << describe(r);
        EXPECT_TRUE(contains(r.err, "npf batch: failed: glossy: " + dir + "/pipe.yaml: is not a regular file: not read\n")) << describe(r);
    }
}

// The configuration and the summaries --merge reads are bounded (text_input.h): /dev/zero and a
// file beyond the cap are refused at once instead of being read until memory runs out.
TEST(BatchHostile, TextInputsAreBounded) {
    const std::string dir = npf::testing::temporary_folder("batch-hostile-bounds");
    RunOptions o;
    o.deadline_s = 30;
    o.memory_cap = std::uint64_t(4) << 30;
    const ToolRun zero = run({"batch", "/dev/zero"}, o);
    EXPECT_EQ(zero.status, 1) << describe(zero);
    EXPECT_TRUE(contains(zero.err, "npf batch: error: /dev/zero: is not a regular file (expected a batch configuration)\n")) << describe(zero);
    const std::string big = dir + "/big.yaml";
    { std::FILE* f = std::fopen(big.c_str(), "w"); std::fclose(f); }
    fs::resize_file(big, (std::uintmax_t(16) << 20) + 1);  // sparse: costs no disk
    const ToolRun large = run({"batch", big}, o);
    EXPECT_EQ(large.status, 1) << describe(large);
    EXPECT_TRUE(contains(large.err, big + ": larger than the 16 MiB a batch configuration may hold: not read")) << describe(large);
    const ToolRun merge = run({"batch", "--merge", "/dev/zero"}, o);
    EXPECT_EQ(merge.status, 1) << describe(merge);
    EXPECT_TRUE(contains(merge.err, "/dev/zero: is not a regular file (expected an npf batch summary)")) << describe(merge);
}

// ---- 4. Outputs against the inputs and each other, by identity ----------------------------------

// Runs a batch over `dir` (in/ -> out/, `extra` settings) expecting it to be refused before any
// work with `message` (`DIR` standing for the folder) on one line.
void expect_refused(const std::string& dir, const std::string& extra, std::string message) {
    for (std::size_t at; (at = message.find("DIR")) != std::string::npos;) message.replace(at, 3, dir);
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out", extra);
    const auto before = tree_of(dir);
    for (const std::vector<std::string>& args : {std::vector<std::string>{"batch", cfg, "--check"}, std::vector<std::string>{"batch", cfg}}) {
        const ToolRun r = run(args);
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_EQ(r.err, "npf batch: error: " + message + "\n") << describe(r);
        EXPECT_FALSE(contains(r.out, "[1/")) << "work was done before the refusal\n" << describe(r);
    }
    EXPECT_EQ(tree_of(dir), before) << "something changed";
}

TEST(BatchHostile, AnOutputThatIsAHardLinkToItsInputIsRefused) {
    const std::string dir = library("batch-hostile-hard-output", {"glossy"});
    fs::create_directories(dir + "/out");
    fs::create_hard_link(dir + "/in/glossy.bsdf", dir + "/out/glossy.exr");
    expect_refused(dir, "", "DIR/out/glossy.exr: is the same file as DIR/in/glossy.bsdf (the input of 'glossy' and the output of "
                            "'glossy'): the output would replace an input");
}

TEST(BatchHostile, AnOutputThatIsALinkToAnInputIsRefused) {
    const std::string dir = library("batch-hostile-link-output", {"glossy", "rough"});
    fs::create_directories(dir + "/out");
    fs::create_symlink("../in/rough.bsdf", dir + "/out/glossy.exr");  // publishing follows it: rough.bsdf replaced
    expect_refused(dir, "", "DIR/out/glossy.exr: is the same file as DIR/in/rough.bsdf (the input of 'rough' and the output of "
                            "'glossy'): the output would replace an input");
}

TEST(BatchHostile, AnInputThatIsAHardLinkToTheSummaryIsRefused) {
    const std::string dir = library("batch-hostile-hard-summary", {"glossy"});
    fs::create_directories(dir + "/out");
    write_text(dir + "/out/batch-summary.json", "an earlier summary");
    fs::create_hard_link(dir + "/out/batch-summary.json", dir + "/in/report.bsdf");
    expect_refused(dir, "", "DIR/out/batch-summary.json: is the same file as DIR/in/report.bsdf (the input of 'report' and the "
                            "summary): the output would replace an input");
}

TEST(BatchHostile, AnInputThatIsAHardLinkToARenderIsRefused) {
    const std::string dir = library("batch-hostile-hard-render", {"glossy"});
    fs::create_directories(dir + "/out/renders");
    write_text(dir + "/out/renders/glossy.studio.npf.exr", "an earlier render");
    fs::create_hard_link(dir + "/out/renders/glossy.studio.npf.exr", dir + "/in/r.bsdf");
    expect_refused(dir, kRenderSettings, "DIR/out/renders/glossy.studio.npf.exr: is the same file as DIR/in/r.bsdf (the input of 'r' and a "
                                         "validation render of 'glossy'): the output would replace an input");
}

TEST(BatchHostile, TwoMaterialsWithOneOutputFileAreRefused) {
    const std::string dir = library("batch-hostile-same-output", {"a", "b"});
    fs::create_directories(dir + "/out");
    write_text(dir + "/out/b.exr", "an earlier output of b");
    fs::create_symlink("b.exr", dir + "/out/a.exr");  // a's texture went into b.exr, then b's replaced it
    expect_refused(dir, "", "DIR/out/b.exr: is the same file as DIR/out/a.exr (the output of 'a' and the output of 'b'): one output "
                            "would replace the other");
}

}  // namespace
