// A batch survives its materials: each one is converted in a worker process of its own
// (`npf batch --worker`), so a reader that crashes, aborts, runs out of memory, hangs or is
// killed fails only its material, which is reported by name and reason while the others convert
// (exit status 4). The crashes are injected with the test-only NPF_TEST_FAULT variable, read
// by the test-only worker executable (NPF_FAULT_WORKER_PATH, tests/fault_worker.cpp) and the
// in-process hook (injected_faults.h), never by npf (docs/batch.md "Failure isolation").
#include "batch_processes.h"
#include "batch_runs.h"
#include "injected_faults.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/batch/config.h>
#include <npf/batch/runner.h>
#include <npf/batch/summary.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include <csignal>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
namespace batch = npf::batch;
using npf::testing::contains;
using npf::testing::describe;
using npf::testing::ToolRun;
using npf::testing::batch_run;
using npf::testing::exr_outputs_of;
using npf::testing::write_batch_config;
using npf::testing::write_test_material;


// The test-only fault variable, set for the tool runs of one test.
class ScopedFault {
public:
    explicit ScopedFault(const std::string& spec) { ::setenv("NPF_TEST_FAULT", spec.c_str(), 1); }
    ~ScopedFault() { ::unsetenv("NPF_TEST_FAULT"); }
    ScopedFault(const ScopedFault&) = delete;
    ScopedFault& operator=(const ScopedFault&) = delete;
};





std::map<std::string, const batch::MaterialResult*> by_name(const batch::BatchSummary& s) {
    std::map<std::string, const batch::MaterialResult*> out;
    for (const batch::MaterialResult& m : s.materials) out[m.name] = &m;
    return out;
}

TEST(BatchIsolation, CrashesAbortsMemoryAndHangsFailOnlyTheirMaterial) {
    const std::string dir = npf::testing::temporary_folder("batch-isolation");
    // Every material is a good file: the faults are injected into their workers.
    const std::vector<std::string> names = {"aborts", "crashes", "glossy", "hog", "killed", "quits", "rough", "stuck"};
    fs::create_directories(dir + "/in");
    for (std::size_t i = 0; i < names.size(); ++i) write_test_material(dir + "/in/" + names[i] + ".bsdf", 0.2f + 0.05f * float(i));
    const std::string limits = "  time_limit: 120\nmaterials:\n  hog: {memory_limit: 1 GiB}\n  stuck: {time_limit: 1.5}\n";
    const std::string cfg = write_batch_config(dir + "/batch.yaml", dir + "/in", dir + "/out", limits);
    ToolRun r;
    {
        const ScopedFault fault("abort:aborts,segv:crashes,oom:hog,kill:killed,exit:quits,hang:stuck");
        r = batch_run({cfg, "--worker-executable", NPF_FAULT_WORKER_PATH});
    }
    EXPECT_EQ(r.status, 4) << describe(r);
    const batch::BatchSummary s = batch::read_summary_json(dir + "/out/batch-summary.json");
    const auto m = by_name(s);
    ASSERT_EQ(m.size(), names.size()) << describe(r);
    const std::map<std::string, std::string> expected = {
        {"aborts", "killed by signal 6 (aborted)"},
        {"crashes", "killed by signal 11 (segmentation fault)"},
        {"hog", "ran out of memory (limit 1 GiB)"},
        {"killed", "killed by signal 9 (killed)"},
        {"quits", "the worker process exited with status 9"},
        {"stuck", "took longer than 1.5 s"},
    };
    for (const auto& [name, reason] : expected) {
        const batch::MaterialResult& got = *m.at(name);
        EXPECT_EQ(got.status, batch::MaterialStatus::Failed) << name;
        // Named by its input file, with the reason.
        EXPECT_TRUE(contains(got.reason, dir + "/in/" + name + ".bsdf: ")) << name << ": " << got.reason;
        EXPECT_TRUE(contains(got.reason, reason)) << name << ": " << got.reason;
        EXPECT_TRUE(contains(r.err, "failed: " + name + ": ")) << name << "\n" << describe(r);
    }
    for (const char* good : {"glossy", "rough"}) {
        EXPECT_EQ(m.at(good)->status, batch::MaterialStatus::Converted) << good << ": " << m.at(good)->reason;
        EXPECT_TRUE(m.at(good)->error_mean) << good;
    }
    // Nothing of the failed ones was published, and nothing is left in the work folder.
    EXPECT_EQ(npf::testing::folder_entries(dir + "/out"),
              (std::vector<std::string>{".npf-batch", "batch-summary.json", "batch-summary.md", "glossy.exr", "rough.exr"}));
    EXPECT_TRUE(npf::testing::folder_entries(dir + "/out/.npf-batch/shard-0-of-1").empty());

    // Without the faults (nor stuck's short limit, which a real conversion on a busy machine may
    // need; limits are not in the content hash) the next run converts the rest and skips what was
    // done; every output is byte for byte what a batch in one process writes.
    write_batch_config(cfg, dir + "/in", dir + "/out", "materials:\n  hog: {memory_limit: 1 GiB}\n");
    const ToolRun again = batch_run({cfg});
    ASSERT_EQ(again.status, 0) << describe(again);
    const batch::BatchSummary t = batch::read_summary_json(dir + "/out/batch-summary.json");
    EXPECT_EQ(t.count(batch::MaterialStatus::Skipped), 2u);
    EXPECT_EQ(t.count(batch::MaterialStatus::Converted), names.size() - 2);
    const std::string in_process = write_batch_config(dir + "/one.yaml", dir + "/in", dir + "/one");
    const ToolRun one = batch_run({in_process, "--in-process", "--quiet"});
    ASSERT_EQ(one.status, 0) << describe(one);
    const auto a = exr_outputs_of(dir + "/out"), b = exr_outputs_of(dir + "/one");
    EXPECT_EQ(a.size(), names.size());
    EXPECT_TRUE(a == b) << "outputs of worker processes differ from those of one process";
}

// In one process (a library caller without a worker executable) running out of memory is
// reported with the file it happened on, not as a bare "std::bad_alloc".
TEST(BatchIsolation, RunningOutOfMemoryInProcessNamesTheFile) {
    const std::string dir = npf::testing::temporary_folder("batch-oom-in-process");
    fs::create_directories(dir + "/in");
    write_test_material(dir + "/in/glossy.bsdf", 0.2f);
    write_test_material(dir + "/in/hog.bsdf", 0.4f);
    const std::string cfg = write_batch_config(dir + "/batch.yaml", dir + "/in", dir + "/out");
    batch::BatchOptions options;  // no worker_executable: in this process
    options.before_material = npf::testing::injected_faults(false);
    batch::BatchSummary s;
    {
        const ScopedFault fault("oom:hog");
        s = batch::run_batch(batch::load_batch_config(cfg), options);
    }
    const auto m = by_name(s);
    ASSERT_EQ(m.size(), 2u);
    EXPECT_EQ(m.at("glossy")->status, batch::MaterialStatus::Converted) << m.at("glossy")->reason;
    EXPECT_EQ(m.at("hog")->status, batch::MaterialStatus::Failed);
    EXPECT_EQ(m.at("hog")->reason, dir + "/in/hog.bsdf: ran out of memory (no memory limit)");
}

// A library caller that names a worker executable gets the same isolation as `npf batch`.
TEST(BatchIsolation, LibraryCallersCanUseWorkerProcesses) {
    const std::string dir = npf::testing::temporary_folder("batch-library-workers");
    fs::create_directories(dir + "/in");
    write_test_material(dir + "/in/glossy.bsdf", 0.2f);
    write_test_material(dir + "/in/crashes.bsdf", 0.4f);
    const std::string cfg = write_batch_config(dir + "/batch.yaml", dir + "/in", dir + "/out");
    batch::BatchOptions options;
    options.worker_executable = NPF_FAULT_WORKER_PATH;
    options.time_limit = "60";
    std::vector<std::string> lines;
    options.log = [&](const std::string& line) { lines.push_back(line); };
    batch::BatchSummary s;
    {
        const ScopedFault fault("segv:crashes");
        s = batch::run_batch(batch::load_batch_config(cfg), options);
    }
    const auto m = by_name(s);
    ASSERT_EQ(m.size(), 2u);
    EXPECT_EQ(m.at("glossy")->status, batch::MaterialStatus::Converted) << m.at("glossy")->reason;
    EXPECT_EQ(m.at("crashes")->status, batch::MaterialStatus::Failed);
    EXPECT_TRUE(contains(m.at("crashes")->reason, "crashes.bsdf: killed by signal 11 (segmentation fault)")) << m.at("crashes")->reason;
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_TRUE(contains(lines[0], "[1/2] crashes: failed: ")) << lines[0];
}

// Whether a process whose command line holds `part` is alive (a zombie counts as gone).
bool process_running(const std::string& part) { return npf::testing::process_with(part) != 0; }

// kill -9 of the batch takes its worker with it: nothing converts on behind the next run's back.
TEST(BatchIsolation, AWorkerDiesWithItsBatch) {
    const std::string dir = npf::testing::temporary_folder("batch-worker-orphan");
    fs::create_directories(dir + "/in");
    write_test_material(dir + "/in/stuck.bsdf", 0.3f);
    const std::string cfg = write_batch_config(dir + "/batch.yaml", dir + "/in", dir + "/out");
    const std::string job = dir + "/out/.npf-batch/shard-0-of-1/stuck.job.yaml";
    pid_t pid = -1;
    {
        const ScopedFault fault("hang:stuck");
        pid = ::fork();
        if (pid == 0) {
            const int fd = ::open((dir + "/batch.log").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (fd >= 0) ::dup2(fd, 1), ::dup2(fd, 2);
            ::execl(NPF_TOOL_PATH, NPF_TOOL_PATH, "batch", cfg.c_str(), "--worker-executable", NPF_FAULT_WORKER_PATH,
                    static_cast<char*>(nullptr));
            ::_exit(127);
        }
    }
    ASSERT_GT(pid, 0);
    bool started = false;
    for (int i = 0; i < 2000 && !started; ++i) {
        started = process_running("--worker " + job);
        if (!started) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(started) << "no worker process was started:\n" << npf::testing::read_text(dir + "/batch.log");
    bool gone = false;
    for (int i = 0; i < 400 && !gone; ++i) {
        gone = !process_running("--worker " + job);
        if (!gone) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_TRUE(gone) << "the worker outlived its batch";
    const ToolRun resumed = batch_run({cfg});
    EXPECT_EQ(resumed.status, 0) << describe(resumed);
}

}  // namespace
