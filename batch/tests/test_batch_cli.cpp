// End-to-end tests of `npf batch` on small synthetic libraries: hostile files reported by name
// and reason with a non-zero status while the good materials convert; re-runs skip; a changed
// setting redoes only its material; a batch killed mid-material resumes to the same bytes as
// an uninterrupted one; two shards give the bytes of one process; summaries merge; a batch
// whose inputs cover its output folder never takes its own files for inputs; the summary's
// folder is checked before anything is converted.
#include "batch_runs.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/batch/summary.h>
#include <npf/materials/tensor_file.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <thread>
#include <vector>

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


npf::testing::SyntheticRglSpec small(bool spectral, float alpha) {
    npf::testing::SyntheticRglSpec s;
    s.theta_count = 5;
    s.ndf_size = 16;
    s.vndf_size = 8;
    s.data_size = 8;
    s.spectral = spectral;
    s.alpha_x = s.alpha_y = alpha;
    return s;
}

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Good materials: three synthetic RGL files. Hostile: a truncated file, garbage bytes and a
// file with a NaN in its data.
void write_library(const std::string& dir, bool hostile) {
    fs::create_directories(dir);
    npf::testing::write_synthetic_rgl(small(false, 0.2f), dir + "/glossy.bsdf");
    npf::testing::write_synthetic_rgl(small(false, 0.5f), dir + "/rough.bsdf");
    npf::testing::write_synthetic_rgl(small(true, 0.3f), dir + "/spectral.bsdf");
    if (!hostile) return;
    std::vector<std::uint8_t> bytes = npf::testing::make_synthetic_rgl(small(false, 0.3f)).serialize();
    bytes.resize(bytes.size() / 2);
    write_bytes(dir + "/truncated.bsdf", bytes);
    std::vector<std::uint8_t> garbage(4096);
    for (std::size_t i = 0; i < garbage.size(); ++i) garbage[i] = std::uint8_t((i * 2654435761u) >> 13);
    write_bytes(dir + "/garbage.bsdf", garbage);
    auto fields = npf::testing::synthetic_rgl_fields(small(false, 0.3f));
    npf::testing::SyntheticField* rgb = npf::testing::find_field(fields, "rgb");
    std::vector<float> v = rgb->floats();
    v[v.size() / 2] = std::numeric_limits<float>::quiet_NaN();
    rgb->set_floats(v);
    npf::testing::to_writer(fields).write(dir + "/nan.bsdf");
}




std::map<std::string, std::string> statuses(const batch::BatchSummary& s) {
    std::map<std::string, std::string> out;
    for (const batch::MaterialResult& m : s.materials) out[m.name] = batch::status_name(m.status);
    return out;
}

TEST(BatchCli, HostileFilesAreReportedAndTheOthersConvert) {
    const std::string dir = npf::testing::temporary_folder("batch-hostile");
    write_library(dir + "/in", true);
    const std::string cfg = write_batch_config(dir + "/batch.yaml", dir + "/in", dir + "/out");
    const ToolRun r = batch_run({cfg});
    EXPECT_EQ(r.status, 4) << describe(r);
    for (const char* bad : {"truncated", "garbage", "nan"}) {
        EXPECT_TRUE(contains(r.err, std::string("failed: ") + bad + ":")) << bad << "\n" << describe(r);
    }
    const batch::BatchSummary s = batch::read_summary_json(dir + "/out/batch-summary.json");
    const std::map<std::string, std::string> want = {{"garbage", "failed"}, {"glossy", "converted"}, {"nan", "failed"},
                                                     {"rough", "converted"}, {"spectral", "converted"}, {"truncated", "failed"}};
    EXPECT_EQ(statuses(s), want);
    for (const batch::MaterialResult& m : s.materials) {
        if (m.name == "nan") {
            EXPECT_TRUE(contains(m.reason, "non-finite")) << m.reason;
        }
        if (m.name == "garbage" || m.name == "truncated") {
            EXPECT_TRUE(contains(m.reason, m.name + ".bsdf")) << m.reason;
        }
        if (m.status == batch::MaterialStatus::Converted) {
            EXPECT_GT(m.output_bytes, 0u);
            EXPECT_TRUE(m.ratio());
            EXPECT_TRUE(m.error_mean);
            ASSERT_TRUE(m.albedo_max);
            EXPECT_GT(*m.albedo_max, 0.0);
        }
    }
    EXPECT_FALSE(s.ok());
    const std::string md = npf::testing::read_text(dir + "/out/batch-summary.md");
    EXPECT_TRUE(contains(md, "| nan | failed |")) << md;
    // Only the good materials have outputs, and nothing else is left in the output folder.
    EXPECT_EQ(npf::testing::folder_entries(dir + "/out"),
              (std::vector<std::string>{".npf-batch", "batch-summary.json", "batch-summary.md", "glossy.exr", "rough.exr",
                                        "spectral.exr"}));
    EXPECT_TRUE(npf::testing::folder_entries(dir + "/out/.npf-batch/shard-0-of-1").empty());
    // The outputs are real factor textures.
    const ToolRun info = npf::testing::run_tool({"info", dir + "/out/glossy.exr"});
    EXPECT_EQ(info.status, 0) << describe(info);
}

TEST(BatchCli, RerunSkipsAndAChangedSettingRedoesOnlyItsMaterial) {
    const std::string dir = npf::testing::temporary_folder("batch-rerun");
    write_library(dir + "/in", false);
    const std::string cfg = write_batch_config(dir + "/batch.yaml", dir + "/in", dir + "/out");
    const ToolRun first = batch_run({cfg, "--quiet"});
    ASSERT_EQ(first.status, 0) << describe(first);
    const auto before = exr_outputs_of(dir + "/out");
    ASSERT_EQ(before.size(), 3u);

    const auto t0 = std::chrono::steady_clock::now();
    const ToolRun again = batch_run({cfg});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_EQ(again.status, 0) << describe(again);
    EXPECT_LT(seconds, 5.0);
    const batch::BatchSummary s = batch::read_summary_json(dir + "/out/batch-summary.json");
    EXPECT_EQ(s.count(batch::MaterialStatus::Skipped), 3u) << again.out;
    for (const batch::MaterialResult& m : s.materials) EXPECT_TRUE(m.error_mean) << m.name;  // read back from the file
    EXPECT_EQ(exr_outputs_of(dir + "/out"), before);

    // A per-material override for one material: only that one is redone.
    write_batch_config(cfg, dir + "/in", dir + "/out", "materials:\n  rough: {error_pairs: 400}\n");
    const ToolRun changed = batch_run({cfg});
    ASSERT_EQ(changed.status, 0) << describe(changed);
    const batch::BatchSummary c = batch::read_summary_json(dir + "/out/batch-summary.json");
    EXPECT_EQ(statuses(c), (std::map<std::string, std::string>{{"glossy", "skipped"}, {"rough", "converted"}, {"spectral", "skipped"}}));
    // A changed input file: only that one is redone.
    npf::testing::write_synthetic_rgl(small(false, 0.25f), dir + "/in/glossy.bsdf");
    const ToolRun touched = batch_run({cfg});
    ASSERT_EQ(touched.status, 0) << describe(touched);
    EXPECT_EQ(statuses(batch::read_summary_json(dir + "/out/batch-summary.json")),
              (std::map<std::string, std::string>{{"glossy", "converted"}, {"rough", "skipped"}, {"spectral", "skipped"}}));
    // --force redoes everything, to the same bytes.
    const auto now = exr_outputs_of(dir + "/out");
    const ToolRun forced = batch_run({cfg, "--force"});
    ASSERT_EQ(forced.status, 0) << describe(forced);
    EXPECT_EQ(batch::read_summary_json(dir + "/out/batch-summary.json").count(batch::MaterialStatus::Converted), 3u);
    EXPECT_EQ(exr_outputs_of(dir + "/out"), now);
}

TEST(BatchCli, TwoShardsGiveTheBytesOfOneProcessAndMerge) {
    const std::string dir = npf::testing::temporary_folder("batch-shards");
    write_library(dir + "/in", true);
    const std::string one = write_batch_config(dir + "/one.yaml", dir + "/in", dir + "/one");
    const std::string two = write_batch_config(dir + "/two.yaml", dir + "/in", dir + "/two");
    EXPECT_EQ(batch_run({one, "--quiet"}).status, 4);
    const ToolRun s0 = batch_run({two, "--shard", "0/2", "--quiet"});
    const ToolRun s1 = batch_run({two, "--shard", "1/2", "--quiet"});
    // Sorted names: garbage glossy nan rough spectral truncated; shard 0 gets garbage, nan,
    // spectral (two of them fail), shard 1 glossy, rough, truncated.
    EXPECT_EQ(s0.status, 4) << describe(s0);
    EXPECT_EQ(s1.status, 4) << describe(s1);
    const auto a = exr_outputs_of(dir + "/one"), b = exr_outputs_of(dir + "/two");
    EXPECT_EQ(a.size(), 3u);
    EXPECT_EQ(a, b);
    const batch::BatchSummary p0 = batch::read_summary_json(dir + "/two/batch-summary.shard-0-of-2.json");
    EXPECT_EQ(statuses(p0), (std::map<std::string, std::string>{{"garbage", "failed"}, {"nan", "failed"}, {"spectral", "converted"}}));
    const ToolRun merged = batch_run({"--merge", dir + "/two/batch-summary.shard-0-of-2.json",
                                      dir + "/two/batch-summary.shard-1-of-2.json", "-o", dir + "/merged"});
    EXPECT_EQ(merged.status, 4) << describe(merged);  // three failed
    const batch::BatchSummary m = batch::read_summary_json(dir + "/merged.json");
    EXPECT_EQ(statuses(m), statuses(batch::read_summary_json(dir + "/one/batch-summary.json")));
    EXPECT_EQ(m.shards, (std::vector<int>{0, 1}));
    EXPECT_TRUE(m.warnings.empty()) << m.warnings.front();
    // One shard alone is incomplete: merging it says so.
    const ToolRun half = batch_run({"--merge", dir + "/two/batch-summary.shard-0-of-2.json", "-o", dir + "/half"});
    EXPECT_EQ(half.status, 4);
    EXPECT_TRUE(contains(half.err, "shard 1 of 2 is missing")) << describe(half);
}

TEST(BatchCli, ConfigurationErrorsNameTheLine) {
    const std::string dir = npf::testing::temporary_folder("batch-config-errors");
    npf::testing::write_text(dir + "/bad.yaml", "output_dir: out\ninputs: '*.bsdf'\ndefaults:\n  preset: quick\n");
    const ToolRun r = batch_run({dir + "/bad.yaml"});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "bad.yaml:4: key 'defaults.preset': 'quick' is not one of")) << describe(r);
    const ToolRun usage = batch_run({});
    EXPECT_EQ(usage.status, 2);
    const ToolRun shard = batch_run({dir + "/bad.yaml", "--shard", "2/2"});
    EXPECT_EQ(shard.status, 1);
}

// A --worker-executable that is not an executable file is refused before anything runs (exit 1,
// the file named, no output folder), rather than failing every material alike.
TEST(BatchCli, AWorkerExecutableThatCannotRunIsRefusedFirst) {
    const std::string dir = npf::testing::temporary_folder("batch-worker-executable");
    fs::create_directories(dir + "/in");
    const std::string cfg = write_batch_config(dir + "/batch.yaml", dir + "/in", dir + "/out");
    npf::testing::write_text(dir + "/not_a_program", "text\n");
    for (const std::string& program : {dir + "/missing", dir + "/not_a_program", dir + "/in"}) {
        const ToolRun r = batch_run({cfg, "--worker-executable", program});
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_TRUE(contains(r.err, program + ": not an executable file (--worker-executable)")) << describe(r);
        EXPECT_FALSE(fs::exists(dir + "/out")) << program;
    }
}

TEST(BatchCli, EditsAndValidationRendersAreApplied) {
    const std::string dir = npf::testing::temporary_folder("batch-edit");
    write_library(dir + "/in", false);
    npf::testing::write_text(dir + "/rotate.yaml", "steps:\n  - rotate: 30\n");
    const std::string cfg = write_batch_config(dir + "/batch.yaml", dir + "/in", dir + "/out",
                                         "  render: {size: 24, spp: 2, threads: 1}\n"
                                         "materials:\n  rough: {edit: rotate.yaml}\n  spectral: {skip: true}\n");
    const ToolRun r = batch_run({cfg});
    ASSERT_EQ(r.status, 0) << describe(r);
    const batch::BatchSummary s = batch::read_summary_json(dir + "/out/batch-summary.json");
    ASSERT_EQ(s.materials.size(), 2u);
    // Judged under the default set, each lighting in its own pair of renders, by the worst.
    const std::vector<std::string> set = {"studio", "key-rim", "directional"};
    for (const batch::MaterialResult& m : s.materials) {
        ASSERT_EQ(m.lightings.size(), 3u) << m.name;
        double worst = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < 3; ++i) {
            const batch::LightingCheck& c = m.lightings[i];
            EXPECT_EQ(c.lighting, set[i]) << m.name;
            EXPECT_GT(c.psnr, 15.0) << m.name << " " << c.lighting;
            worst = std::min(worst, c.psnr);
            // A map's PSNR comes with its paired noise floor, which a real render never reaches
            // infinity on (2 spp of environment sampling); directional lights have no noise.
            if (c.lighting == "directional") EXPECT_TRUE(std::isinf(c.psnr_floor)) << m.name;
            else EXPECT_TRUE(std::isfinite(c.psnr_floor) && c.psnr_floor > 0.0) << m.name << " " << c.psnr_floor;
        }
        ASSERT_TRUE(m.psnr) << m.name;
        EXPECT_EQ(*m.psnr, worst) << m.name;
        EXPECT_EQ(m.edits.size(), m.name == "rough" ? 1u : 0u) << m.name;
    }
    EXPECT_TRUE(contains(r.out + r.err, ", the worst of studio ")) << describe(r);
    EXPECT_TRUE(contains(r.out + r.err, "(floor ")) << describe(r);
    std::vector<std::string> renders;
    for (const char* name : {"glossy", "rough"})
        for (const std::string& l : set)
            for (const char* kind : {"npf", "reference"}) renders.push_back(std::string(name) + "." + l + "." + kind + ".exr");
    std::sort(renders.begin(), renders.end());
    EXPECT_EQ(npf::testing::folder_entries(dir + "/out/renders"), renders);
    // Re-run: nothing to do, and the metrics come back from the files.
    const ToolRun again = batch_run({cfg});
    ASSERT_EQ(again.status, 0) << describe(again);
    const batch::BatchSummary t = batch::read_summary_json(dir + "/out/batch-summary.json");
    EXPECT_EQ(t.count(batch::MaterialStatus::Skipped), 2u);
    EXPECT_DOUBLE_EQ(*t.materials[0].psnr, *s.materials[0].psnr);
    ASSERT_EQ(t.materials[0].lightings.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(t.materials[0].lightings[i].lighting, set[i]);
        EXPECT_DOUBLE_EQ(t.materials[0].lightings[i].psnr, s.materials[0].lightings[i].psnr);
        EXPECT_EQ(t.materials[0].lightings[i].psnr_floor, s.materials[0].lightings[i].psnr_floor);
    }
    // A changed recipe redoes its material only.
    npf::testing::write_text(dir + "/rotate.yaml", "steps:\n  - rotate: 45\n");
    ASSERT_EQ(batch_run({cfg}).status, 0);
    EXPECT_EQ(statuses(batch::read_summary_json(dir + "/out/batch-summary.json")),
              (std::map<std::string, std::string>{{"glossy", "skipped"}, {"rough", "converted"}}));
}

// Starts the tool in the background with its output in `log`; returns its pid.
pid_t spawn_tool(const std::vector<std::string>& args, const std::string& log) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) ::dup2(fd, 1), ::dup2(fd, 2);
        std::vector<char*> argv;
        static std::string tool = NPF_TOOL_PATH;
        argv.push_back(tool.data());
        std::vector<std::string> copy = args;
        for (std::string& a : copy) argv.push_back(a.data());
        argv.push_back(nullptr);
        ::execv(tool.c_str(), argv.data());
        ::_exit(127);
    }
    return pid;
}

TEST(BatchCli, KilledMidMaterialResumesToTheSameBytes) {
    const std::string dir = npf::testing::temporary_folder("batch-kill");
    write_library(dir + "/in", false);
    // A slower second material (in name order) so that the kill lands inside its conversion.
    auto slow = small(true, 0.3f);
    slow.phi_count = 4;
    npf::testing::write_synthetic_rgl(slow, dir + "/in/middle.bsdf");
    // About a second: 200 sweeps (no early stop) on a small anisotropic grid.
    const std::string extra = "materials:\n  middle: {grid: [24, 32, 24, 32], g_grid: [24, 32], phi_d_samples: 8,"
                              " iterations: 200, tolerance: 0}\n";
    const std::string ref_cfg = write_batch_config(dir + "/ref.yaml", dir + "/in", dir + "/ref", extra);
    const std::string cfg = write_batch_config(dir + "/batch.yaml", dir + "/in", dir + "/out", extra);
    const ToolRun ref = batch_run({ref_cfg, "--quiet"});
    ASSERT_EQ(ref.status, 0) << describe(ref);

    // Names in order: glossy, middle, rough, spectral. Kill once glossy is done.
    const std::string log = dir + "/killed.log";
    const pid_t pid = spawn_tool({"batch", cfg}, log);
    ASSERT_GT(pid, 0);
    bool started = false;
    for (int i = 0; i < 3000 && !started; ++i) {
        started = contains(npf::testing::read_text(log), "[1/4] glossy");
        if (!started) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_TRUE(started) << npf::testing::read_text(log);
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status));
    const std::string text = npf::testing::read_text(log);
    ASSERT_FALSE(contains(text, "[2/4] middle")) << "the kill came too late to interrupt a conversion:\n" << text;
    // No partial output: the interrupted material has no file under its name, nor a temporary
    // beside the outputs (temporaries live in .npf-batch/, cleared by the next run).
    EXPECT_EQ(npf::testing::folder_entries(dir + "/out"), (std::vector<std::string>{".npf-batch", "glossy.exr"}));

    const ToolRun resumed = batch_run({cfg});
    ASSERT_EQ(resumed.status, 0) << describe(resumed);
    EXPECT_EQ(statuses(batch::read_summary_json(dir + "/out/batch-summary.json")),
              (std::map<std::string, std::string>{{"glossy", "skipped"}, {"middle", "converted"}, {"rough", "converted"},
                                                  {"spectral", "converted"}}));
    EXPECT_TRUE(npf::testing::folder_entries(dir + "/out/.npf-batch/shard-0-of-1").empty());
    const auto a = exr_outputs_of(dir + "/ref"), b = exr_outputs_of(dir + "/out");
    EXPECT_EQ(a.size(), 4u);
    EXPECT_TRUE(a == b) << "outputs of the resumed batch differ from the uninterrupted one";
}

// Inputs that cover the output folder: the batch's outputs, renders and summaries are not taken
// for inputs, so the second run has nothing to do (it used to fail on "two inputs are named
// 'batch-summary'", or, with the summary elsewhere, convert p_npf.exr into p_npf_npf.exr).
TEST(BatchCli, AGlobOverTheOutputFolderNeverFeedsOnTheBatchsOwnFiles) {
    const std::string dir = npf::testing::temporary_folder("batch-self-feed");
    write_library(dir + "/lib", false);
    const std::string cfg = dir + "/batch.yaml";
    npf::testing::write_text(cfg, "output_dir: lib\ninputs: ['lib/*']\n" + std::string(npf::testing::kBatchTestDefaults) +
                                      "  render: {size: 16, spp: 1, threads: 1}\n");
    const ToolRun first = batch_run({cfg, "--quiet"});
    ASSERT_EQ(first.status, 0) << describe(first);
    const std::vector<std::string> after_first = npf::testing::folder_entries(dir + "/lib");
    for (int run = 0; run < 2; ++run) {
        const ToolRun again = batch_run({cfg});
        ASSERT_EQ(again.status, 0) << describe(again);
        const batch::BatchSummary s = batch::read_summary_json(dir + "/lib/batch-summary.json");
        EXPECT_EQ(statuses(s), (std::map<std::string, std::string>{{"glossy", "skipped"}, {"rough", "skipped"}, {"spectral", "skipped"}}))
            << describe(again);
        EXPECT_EQ(npf::testing::folder_entries(dir + "/lib"), after_first);
    }

    // Outputs that are NPF textures (valid inputs) named by `naming` beside their inputs, the
    // summary elsewhere: p_npf.exr is an output, never the input of p_npf_npf.exr.
    const std::string cfg2 = dir + "/named.yaml";
    npf::testing::write_text(cfg2, "output_dir: lib2\nnaming: '{name}_npf.exr'\nsummary: sums/s\ninputs: ['lib2/*']\n" +
                                       std::string(npf::testing::kBatchTestDefaults));
    fs::create_directories(dir + "/lib2");
    fs::copy_file(dir + "/lib/glossy.exr", dir + "/lib2/p.exr");  // an NPF texture as an input
    fs::copy_file(dir + "/lib/rough.bsdf", dir + "/lib2/q.bsdf");
    const ToolRun named = batch_run({cfg2, "--quiet"});
    ASSERT_EQ(named.status, 0) << describe(named);
    const std::vector<std::string> want = {".npf-batch", "p.exr", "p_npf.exr", "q.bsdf", "q_npf.exr"};
    EXPECT_EQ(npf::testing::folder_entries(dir + "/lib2"), want);
    for (int run = 0; run < 2; ++run) {
        const ToolRun again = batch_run({cfg2});
        ASSERT_EQ(again.status, 0) << describe(again);
        EXPECT_EQ(statuses(batch::read_summary_json(dir + "/sums/s.json")),
                  (std::map<std::string, std::string>{{"p", "skipped"}, {"q", "skipped"}}))
            << describe(again);
        EXPECT_EQ(npf::testing::folder_entries(dir + "/lib2"), want);
    }
}

// A batch publishes its outputs by the rules of every npf writer (docs/reliability.md sec. 1),
// not by renaming its staged files over whatever is there: a link at an output's name is
// followed (the link stays, its target gets the texture), a folder there is that material's
// failure while the others convert, and a temporary left by a killed run is never an input.
TEST(BatchCli, OutputsArePublishedByTheRulesOfEveryWriter) {
    const std::string dir = npf::testing::temporary_folder("batch-publish-rules");
    write_library(dir + "/out", false);  // inputs and outputs in one folder
    fs::create_directories(dir + "/kept");
    npf::testing::write_text(dir + "/kept/glossy-target.exr", "the link's target before the batch");
    fs::create_symlink("../kept/glossy-target.exr", dir + "/out/glossy.exr");
    fs::create_directories(dir + "/out/rough.exr");
    npf::testing::write_text(dir + "/out/spectral.exr.tmp-0123456789abcdef", "left by a killed run");
    const std::string cfg = dir + "/batch.yaml";
    npf::testing::write_text(cfg, "output_dir: out\ninputs: ['out/*']\n" + std::string(npf::testing::kBatchTestDefaults));
    const ToolRun r = batch_run({cfg, "--quiet"});
    EXPECT_EQ(r.status, 4) << describe(r);
    const batch::BatchSummary s = batch::read_summary_json(dir + "/out/batch-summary.json");
    EXPECT_EQ(statuses(s), (std::map<std::string, std::string>{{"glossy", "converted"}, {"rough", "failed"}, {"spectral", "converted"}}))
        << describe(r);
    for (const batch::MaterialResult& m : s.materials) {
        if (m.name == "rough") {
            EXPECT_TRUE(contains(m.reason, "is a directory")) << m.reason;
        }
    }
    ASSERT_TRUE(fs::is_symlink(dir + "/out/glossy.exr"));
    EXPECT_EQ(fs::read_symlink(dir + "/out/glossy.exr"), fs::path("../kept/glossy-target.exr"));
    const ToolRun info = npf::testing::run_tool({"info", dir + "/kept/glossy-target.exr"});
    EXPECT_EQ(info.status, 0) << describe(info);
    EXPECT_TRUE(fs::is_directory(dir + "/out/rough.exr"));
    EXPECT_TRUE(fs::is_regular_file(dir + "/out/spectral.exr"));
    EXPECT_TRUE(npf::testing::folder_entries(dir + "/out/.npf-batch/shard-0-of-1").empty());
}

// A summary in a folder that does not exist yet is written (the folder is made before any
// conversion); one that cannot be made fails --check, and a run before it converts anything.
TEST(BatchCli, TheSummaryFolderIsMadeOrRefusedBeforeConverting) {
    const std::string dir = npf::testing::temporary_folder("batch-summary-folder");
    write_library(dir + "/in", false);
    const std::string cfg = write_batch_config(dir + "/batch.yaml", dir + "/in", dir + "/out", "summary: reports/2024/lib\n");
    const ToolRun check = batch_run({cfg, "--check"});
    EXPECT_EQ(check.status, 0) << describe(check);
    EXPECT_FALSE(fs::exists(dir + "/reports")) << "--check made a folder";
    const ToolRun r = batch_run({cfg, "--quiet"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(batch::read_summary_json(dir + "/reports/2024/lib.json").count(batch::MaterialStatus::Converted), 3u);

    npf::testing::write_text(dir + "/blocker", "a file where the summary's folder would go");
    const std::string bad = write_batch_config(dir + "/bad.yaml", dir + "/in", dir + "/bad-out", "summary: blocker/lib\n");
    const ToolRun refused = batch_run({bad, "--check"});
    EXPECT_EQ(refused.status, 1) << describe(refused);
    EXPECT_TRUE(contains(refused.err, "summary folder")) << describe(refused);
    EXPECT_TRUE(contains(refused.err, dir + "/blocker is not a folder")) << describe(refused);
    const ToolRun run = batch_run({bad});
    EXPECT_EQ(run.status, 1) << describe(run);
    EXPECT_TRUE(contains(run.err, "summary folder")) << describe(run);
    EXPECT_TRUE(exr_outputs_of(dir + "/bad-out").empty()) << "converted before finding out the summary cannot be written";
    // The same for --summary.
    const ToolRun flag = batch_run({cfg, "--check", "--summary", dir + "/blocker/x"});
    EXPECT_EQ(flag.status, 1) << describe(flag);
}

}  // namespace

