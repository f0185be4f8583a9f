// Publishing outputs from the command line: /dev/null, a full device, FIFOs and links at the
// destination, folders refused before any work, planted temporaries not followed.
#include "publish_checks.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/core/atomic_file.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

namespace {

using namespace npf::testing::publish;

// Item 1 of issue 17: `-o /dev/null` replaced the device node with a regular file.
TEST(PublishCli, DevNullDiscardsTheOutputOfEveryWriter) {
    const std::string dir = npf::testing::temporary_folder("publish-cli");
    const std::string null = null_destination(dir);
    if (null.empty()) GTEST_SKIP() << "root, and no device node can be made here: not trying the real /dev/null";
    for (const Writer& w : writers()) {
        const ToolRun r = npf::testing::run_tool(w.args(null));
        EXPECT_EQ(r.status, 0) << describe(r);
        EXPECT_EQ(r.err, "") << describe(r);
        ASSERT_TRUE(is_char_device(null, 3)) << w.command << " replaced " << null << "\n" << describe(r);
        // convert reports what it wrote, not the size of the device (0 bytes).
        if (w.command == "convert") {
            EXPECT_EQ(r.out.find(" (0 bytes)"), std::string::npos) << describe(r);
            EXPECT_NE(r.out.find(" bytes)"), std::string::npos) << describe(r);
        }
    }
    const ToolRun r = npf::testing::run_tool(render_png_args(null, null));
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(is_char_device(null, 3)) << describe(r);
    EXPECT_FALSE(has_temporaries(dir));
}

TEST(PublishCli, FullDeviceFailsWithTheReasonAndStaysADevice) {
    const std::string dir = npf::testing::temporary_folder("publish-cli");
    const std::string full = device_node(dir, "full", 7);
    if (full.empty()) GTEST_SKIP() << "no device node can be made here";
    for (const Writer& w : writers()) {
        const ToolRun r = npf::testing::run_tool(w.args(full));
        expect_one_line_error(r, w.command, full, std::strerror(ENOSPC));
        ASSERT_TRUE(is_char_device(full, 7)) << w.command << " replaced " << full << "\n" << describe(r);
    }
    EXPECT_FALSE(has_temporaries(dir));
}

// The PNG fails (a device that takes nothing) after the EXR is complete: neither is published,
// the earlier EXR stays. Before, the EXR was published and then deleted again.
TEST(PublishCli, RenderKeepsTheEarlierExrWhenItsPngFails) {
    const std::string dir = npf::testing::temporary_folder("publish-cli");
    const std::string full = device_node(dir, "full", 7);
    if (full.empty()) GTEST_SKIP() << "no device node can be made here";
    const std::string exr = dir + "/out.exr";
    ASSERT_EQ(npf::testing::run_tool(render_args(exr)).status, 0);
    const std::string earlier = read_text(exr);
    const ToolRun r = npf::testing::run_tool(render_png_args(exr, full));
    expect_one_line_error(r, "render", full, std::strerror(ENOSPC));
    EXPECT_TRUE(read_text(exr) == earlier) << "the earlier render changed";
    EXPECT_TRUE(is_char_device(full, 7));
    EXPECT_FALSE(has_temporaries(dir));
}

TEST(PublishCli, FifoGetsTheBytesAndStaysAFifo) {
    const std::string dir = npf::testing::temporary_folder("publish-cli");
    const std::string fifo = dir + "/fifo", captured = dir + "/captured";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
    // A reader in the background; bounded, so that a regression (no writer ever opens the FIFO)
    // fails instead of hanging.
    const auto through_fifo = [&](const std::vector<std::string>& args) {
        return run_script("timeout 20 cat " + shell_quote(fifo) + " >" + shell_quote(captured) + " & " + tool_command(args) +
                          "; rc=$?; wait; exit $rc");
    };
    const ToolRun synth = through_fifo(synth_args(fifo));
    EXPECT_EQ(synth.status, 0) << describe(synth);
    ASSERT_EQ(npf::testing::run_tool(synth_args(dir + "/regular.bsdf")).status, 0);
    EXPECT_TRUE(read_text(captured) == read_text(dir + "/regular.bsdf")) << "the FIFO got other bytes than a file";
    EXPECT_EQ(kind_of(fifo), mode_t(S_IFIFO));

    // The multi-part factor texture, written by name inside OpenImageIO, goes through too.
    const ToolRun convert = through_fifo(convert_args(fifo));
    EXPECT_EQ(convert.status, 0) << describe(convert);
    ASSERT_EQ(::rename(captured.c_str(), (dir + "/captured.exr").c_str()), 0);
    const ToolRun info = npf::testing::run_tool({"info", dir + "/captured.exr"});
    EXPECT_EQ(info.status, 0) << describe(info);
    EXPECT_TRUE(contains(info.out, "NPF factor texture")) << info.out;
    EXPECT_EQ(kind_of(fifo), mode_t(S_IFIFO));
    EXPECT_FALSE(has_temporaries(dir));
}

TEST(PublishCli, SymbolicLinkIsFollowedAndKept) {
    const std::string dir = npf::testing::temporary_folder("publish-cli");
    ASSERT_TRUE(write_text(dir + "/real.bsdf", "old"));
    const std::string link = dir + "/link.bsdf";
    ASSERT_EQ(::symlink("real.bsdf", link.c_str()), 0);
    const ToolRun r = npf::testing::run_tool(synth_args(link));
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(kind_of(link), mode_t(S_IFLNK)) << "the link was replaced";
    ASSERT_EQ(npf::testing::run_tool(synth_args(dir + "/regular.bsdf")).status, 0);
    EXPECT_TRUE(read_text(dir + "/real.bsdf") == read_text(dir + "/regular.bsdf"));

    const std::string dangling = dir + "/dangling.bsdf";
    ASSERT_EQ(::symlink("nowhere.bsdf", dangling.c_str()), 0);
    const ToolRun d = npf::testing::run_tool(synth_args(dangling));
    expect_one_line_error(d, "synth", dangling, "is a symbolic link to nowhere.bsdf, which does not exist");
    EXPECT_EQ(kind_of(dangling), mode_t(S_IFLNK));
    EXPECT_EQ(kind_of(dir + "/nowhere.bsdf"), mode_t(0));
    EXPECT_FALSE(has_temporaries(dir));
}

// A folder at -o fails at once, before the work, with a message that says so.
TEST(PublishCli, DirectoryIsRefusedBeforeAnyWork) {
    const std::string dir = npf::testing::temporary_folder("publish-cli");
    const std::string folder = dir + "/taken";
    ASSERT_EQ(::mkdir(folder.c_str(), 0755), 0);
    for (const Writer& w : writers()) {
        const ToolRun r = npf::testing::run_tool(w.args(folder));
        expect_one_line_error(r, w.command, folder, "is a directory, not a file");
        EXPECT_EQ(r.out, "") << "work done before the output was checked\n" << describe(r);
    }
    const ToolRun r = npf::testing::run_tool(render_png_args(dir + "/out.exr", folder));
    expect_one_line_error(r, "render", folder, "is a directory, not a file");
    EXPECT_TRUE(folder_entries(folder).empty());
    EXPECT_EQ(folder_entries(dir), std::vector<std::string>{"taken"});
}

// Item 3 of issue 17, through the tool: the shell plants links at the names the old scheme gave
// the temporaries (`<out>.tmp-<pid>-<n>`; exec keeps the shell's pid), then runs npf.
TEST(PublishCli, PlantedTemporaryLinksAreNotFollowed) {
    const std::string dir = npf::testing::temporary_folder("publish-cli");
    const std::string victim = dir + "/victim.txt";
    struct Case {
        std::string command;
        std::vector<std::string> outputs, args;
    };
    const std::vector<Case> cases = {
        {"synth", {dir + "/a.bsdf"}, synth_args(dir + "/a.bsdf")},
        {"convert", {dir + "/b.exr"}, convert_args(dir + "/b.exr")},
        {"render", {dir + "/c.exr", dir + "/c.png"}, render_png_args(dir + "/c.exr", dir + "/c.png")},
        {"display", {dir + "/d.png"}, display_args(dir + "/d.png")},
    };
    for (const Case& c : cases) {
        ASSERT_TRUE(write_text(victim, "precious"));
        std::string plant;
        for (const std::string& out : c.outputs)
            plant += "for k in 0 1 2 3 4 5 6 7; do ln -s " + shell_quote(victim) + " " + shell_quote(out) + ".tmp-$$-$k; done; ";
        const ToolRun r = run_script(plant + "exec " + tool_command(c.args));
        EXPECT_EQ(r.status, 0) << describe(r);
        EXPECT_EQ(read_text(victim), "precious") << c.command << " wrote through a planted link";
        for (const std::string& out : c.outputs) EXPECT_EQ(kind_of(out), mode_t(S_IFREG)) << out;
    }
}

}  // namespace
