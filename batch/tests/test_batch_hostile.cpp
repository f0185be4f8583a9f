// `npf batch` against a hostile file system (issue 33, docs/reliability.md sec. 3): links planted
// at the places the batch owns (its work folder, shard folder, lock, renders, default summary)
// are refused with a line naming them, and nothing outside the output folder changes (processes
// that die or compete: test_batch_hostile_processes.cpp); read-only folders; a glob that
// meets a FIFO, a socket, a device or a dangling link says so; control characters in file names
// never split a line; text inputs are bounded; an output that is an input (through a link or a
// hard link) or another output is refused before any work.
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
using npf::testing::contains;
using npf::testing::describe;
using npf::testing::material_library;
using npf::testing::read_text;
using npf::testing::reason_of;
using npf::testing::RunOptions;
using npf::testing::statuses;
using npf::testing::ToolRun;
using npf::testing::tree_of;
using npf::testing::write_batch_config;
using npf::testing::write_test_material;
using npf::testing::write_text;

// `npf args...` run to its end (or its deadline).
ToolRun run(const std::vector<std::string>& args, const RunOptions& o = {}) { return npf::testing::run_npf(args, o); }

// A victim tree outside the output folder: files and a folder with a file.
void write_victim(const std::string& victim) {
    fs::create_directories(victim + "/sub");
    write_text(victim + "/precious.txt", "keep me");
    write_text(victim + "/sub/deeper.txt", "keep me too");
}

// ---- 1. The batch's own places never follow links ----------------------------------------------

// The reviewed case: a link at the shard folder made every file and folder in its target go
// (clear_folder iterated through it) and exit 0. Now it is refused, and nothing outside the
// output folder changes.
TEST(BatchHostile, ALinkAtTheShardFolderIsRefusedAndNothingOutsideChanges) {
    const std::string dir = material_library("batch-hostile-shard-link", {"glossy"});
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
    const std::string dir = material_library("batch-hostile-work-link", {"glossy"});
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
    const std::string dir = material_library("batch-hostile-lock-link", {"glossy"});
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
    const std::string dir = material_library("batch-hostile-renders-link", {"glossy"});
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
    const std::string dir = material_library("batch-hostile-render-file-link", {"glossy"});
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
    const std::string dir = material_library("batch-hostile-summary-link", {"glossy"});
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
    const std::string dir = material_library("batch-hostile-user-links", {"glossy"});
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
    const std::string dir = material_library("batch-hostile-read-only", {"glossy"});
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
    const std::string dir = material_library("batch-hostile-glob", {"glossy"});
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
    const std::string dir = material_library("batch-hostile-control", {});
    write_test_material(dir + "/in/new\nline.bsdf", 0.3f);
    write_test_material(dir + "/in/esc\x1b[31mred.bsdf", 0.4f);
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
    const std::string dir = material_library("batch-hostile-edit-fifo", {"glossy"});
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
    const std::string dir = material_library("batch-hostile-hard-output", {"glossy"});
    fs::create_directories(dir + "/out");
    fs::create_hard_link(dir + "/in/glossy.bsdf", dir + "/out/glossy.exr");
    expect_refused(dir, "", "DIR/out/glossy.exr: is the same file as DIR/in/glossy.bsdf (the input of 'glossy' and the output of "
                            "'glossy'): the output would replace an input");
}

TEST(BatchHostile, AnOutputThatIsALinkToAnInputIsRefused) {
    const std::string dir = material_library("batch-hostile-link-output", {"glossy", "rough"});
    fs::create_directories(dir + "/out");
    fs::create_symlink("../in/rough.bsdf", dir + "/out/glossy.exr");  // publishing follows it: rough.bsdf replaced
    expect_refused(dir, "", "DIR/out/glossy.exr: is the same file as DIR/in/rough.bsdf (the input of 'rough' and the output of "
                            "'glossy'): the output would replace an input");
}

TEST(BatchHostile, AnInputThatIsAHardLinkToTheSummaryIsRefused) {
    const std::string dir = material_library("batch-hostile-hard-summary", {"glossy"});
    fs::create_directories(dir + "/out");
    write_text(dir + "/out/batch-summary.json", "an earlier summary");
    fs::create_hard_link(dir + "/out/batch-summary.json", dir + "/in/report.bsdf");
    expect_refused(dir, "", "DIR/out/batch-summary.json: is the same file as DIR/in/report.bsdf (the input of 'report' and the "
                            "summary): the output would replace an input");
}

TEST(BatchHostile, AnInputThatIsAHardLinkToARenderIsRefused) {
    const std::string dir = material_library("batch-hostile-hard-render", {"glossy"});
    fs::create_directories(dir + "/out/renders");
    write_text(dir + "/out/renders/glossy.studio.npf.exr", "an earlier render");
    fs::create_hard_link(dir + "/out/renders/glossy.studio.npf.exr", dir + "/in/r.bsdf");
    expect_refused(dir, kRenderSettings, "DIR/out/renders/glossy.studio.npf.exr: is the same file as DIR/in/r.bsdf (the input of 'r' and a "
                                         "validation render of 'glossy'): the output would replace an input");
}

TEST(BatchHostile, TwoMaterialsWithOneOutputFileAreRefused) {
    const std::string dir = material_library("batch-hostile-same-output", {"a", "b"});
    fs::create_directories(dir + "/out");
    write_text(dir + "/out/b.exr", "an earlier output of b");
    fs::create_symlink("b.exr", dir + "/out/a.exr");  // a's texture went into b.exr, then b's replaced it
    expect_refused(dir, "", "DIR/out/b.exr: is the same file as DIR/out/a.exr (the output of 'a' and the output of 'b'): one output "
                            "would replace the other");
}

}  // namespace
