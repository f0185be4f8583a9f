// `npf batch` against processes that die or compete (issue 33, docs/reliability.md sec. 3): a
// worker or the batch itself killed or terminated mid-material leaves nothing behind and the next
// run resumes to the same bytes; two batches over one output folder; a worker uses only the stage
// its batch made. Hangs are injected by the tests' fault-injecting worker (NPF_FAULT_WORKER_PATH).
#include "batch_processes.h"
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
// The batch's process helpers (batch_processes.h) and tool runs (run_tool.h, batch_runs.h).
using namespace npf::testing;

// `npf batch CONFIG` started in the background, material `name` hanging in the tests'
// fault-injecting worker; its output into `log` + ".out" / ".err".
pid_t start_with_hanging(const std::string& config, const std::string& name, const std::string& log) {
    RunOptions hang;
    hang.env = {"NPF_TEST_FAULT=hang:" + name};
    return start_tool({"batch", config, "--worker-executable", NPF_FAULT_WORKER_PATH}, log, hang);
}

// The next run converts `converted` and skips glossy, to the bytes of an uninterrupted batch.
void expect_resumes(const std::string& dir, const std::string& cfg, const std::string& converted) {
    const ToolRun resumed = run_npf({"batch", cfg});
    ASSERT_EQ(resumed.status, 0) << describe(resumed);
    EXPECT_EQ(statuses(dir + "/out/batch-summary.json"),
              (std::map<std::string, std::string>{{"glossy", "skipped"}, {converted, "converted"}}));
    EXPECT_TRUE(exr_outputs_of(dir + "/ref") == exr_outputs_of(dir + "/out"));
}

// Two materials, the second (in name order) slow enough (about a second) to be caught converting.
std::string slow_library(const std::string& tag, std::string& extra) {
    const std::string dir = material_library(tag, {"glossy"});
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
    ASSERT_EQ(run_npf({"batch", ref, "--quiet"}).status, 0);
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
    expect_resumes(dir, cfg, "middle");
}

// SIGTERM of the batch (Slurm's scancel, a timeout) while a worker converts: the worker is killed,
// the stage emptied, no summary written, and the batch ends by SIGTERM; it used to die leaving
// the job file and the worker's log in the stage. The next run resumes to the same bytes.
TEST(BatchHostile, SigtermOfTheBatchLeavesNothingBehindAndTheNextRunResumes) {
    const std::string dir = material_library("batch-hostile-sigterm", {"glossy", "stuck"});
    const std::string ref = write_batch_config(dir + "/ref.yaml", dir + "/in", dir + "/ref");
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out");
    ASSERT_EQ(run_npf({"batch", ref, "--quiet"}).status, 0);
    const pid_t batch_pid = start_with_hanging(cfg, "stuck", dir + "/stopped");
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

    expect_resumes(dir, cfg, "stuck");
}

// Two batches on one output folder at once: the same shard (of the same or of another
// configuration) is refused by its lock, naming it; other shard counts run side by side, each in
// its own stage, converting some materials twice into the same bytes.
TEST(BatchHostile, TwoBatchesOnOneOutputFolder) {
    const std::string dir = material_library("batch-hostile-two-batches", {"a", "b"});
    fs::create_directories(dir + "/hang");
    write_test_material(dir + "/hang/stuck.bsdf", 0.45f);
    const std::string ref = write_batch_config(dir + "/ref.yaml", dir + "/in", dir + "/ref");
    const std::string cfg = write_batch_config(dir + "/b.yaml", dir + "/in", dir + "/out");
    const std::string holding = write_batch_config(dir + "/holding.yaml", dir + "/hang", dir + "/out");
    ASSERT_EQ(run_npf({"batch", ref, "--quiet"}).status, 0);

    const pid_t holder = start_with_hanging(holding, "stuck", dir + "/holder");
    ASSERT_GT(wait_for_worker(dir + "/out", "stuck"), 0) << read_text(dir + "/holder.err");
    const std::string held = "npf batch: error: " + dir +
                             "/out/.npf-batch/shard-0-of-1.lock: another npf batch is running this shard in this output folder "
                             "(the lock is held)";
    for (const std::string& config : {holding, cfg}) {
        const ToolRun second = run_npf({"batch", config});
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
    const ToolRun swapped = run_npf({"batch", "--worker", dir + "/stage/m.job.yaml"});
    EXPECT_EQ(swapped.status, 3) << describe(swapped);
    EXPECT_TRUE(contains(swapped.err, "npf batch --worker: " + dir + "/stage: is not the folder npf batch made (another was put in its place): not used"))
        << describe(swapped);
    write_text(dir + "/elsewhere/m.job.yaml", job(stage));
    const ToolRun foreign = run_npf({"batch", "--worker", dir + "/elsewhere/m.job.yaml"});
    EXPECT_EQ(foreign.status, 3) << describe(foreign);
    EXPECT_TRUE(contains(foreign.err, dir + "/elsewhere/m.job.yaml: is not a job in the work folder the batch made: not used"))
        << describe(foreign);
    EXPECT_TRUE(npf::testing::folder_entries(dir + "/stage") == std::vector<std::string>{"m.job.yaml"});
}

}  // namespace
