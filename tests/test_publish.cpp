// Publishing outputs (docs/reliability.md, "1. Publishing outputs"): what is at the destination
// decides how an output is published (a regular file replaced atomically, a link followed, a
// device or FIFO written through, a folder or socket refused), the temporary cannot be hijacked,
// and every writer (convert, synth, render with and without --png, edit, display) goes through
// it. The fault tests (PublishFaults) fill the disk during each writer: under a file size limit
// (always) and on a real tmpfs (where mount is permitted), and find the earlier outputs intact.
//
// Device nodes are private copies made with mknod in the test folder (the null device, 1:3, and
// the full device, 1:7), so that a regression replaces a node there, never the machine's /dev/null.
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/core/atomic_file.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

using npf::testing::contains;
using npf::testing::describe;
using npf::testing::folder_entries;
using npf::testing::lines_of;
using npf::testing::read_text;
using npf::testing::shell_quote;
using npf::testing::ToolRun;
using npf::testing::write_text;

// ---- Helpers ----------------------------------------------------------------------------------

mode_t kind_of(const std::string& path) {
    struct stat st {};
    return ::lstat(path.c_str(), &st) == 0 ? (st.st_mode & S_IFMT) : 0;
}

bool is_char_device(const std::string& path, unsigned minor) {
    struct stat st {};
    return ::lstat(path.c_str(), &st) == 0 && S_ISCHR(st.st_mode) && st.st_rdev == makedev(1, minor);
}

// A private node for the memory device `minor` (3: null, 7: full) in `dir`; "" where nodes cannot
// be made or opened (not root, a nodev mount).
std::string device_node(const std::string& dir, const std::string& name, unsigned minor) {
    const std::string path = dir + "/" + name;
    if (::mknod(path.c_str(), S_IFCHR | 0666, makedev(1, minor)) != 0) return "";
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) {
        ::unlink(path.c_str());
        return "";
    }
    ::close(fd);
    return path;
}

// Where `-o /dev/null` is tried: a private null node; the real /dev/null only when not root
// (a regression then fails with EACCES instead of replacing it); "" (skip) otherwise.
std::string null_destination(const std::string& dir) {
    const std::string node = device_node(dir, "null", 3);
    if (!node.empty()) return node;
    return ::geteuid() != 0 ? "/dev/null" : "";
}

bool has_temporaries(const std::string& dir) {
    for (const std::string& name : folder_entries(dir))
        if (contains(name, ".tmp-")) return true;
    return false;
}

std::string tool_command(const std::vector<std::string>& args) {
    std::string c = shell_quote(NPF_TOOL_PATH);
    for (const std::string& a : args) c += " " + shell_quote(a);
    return c;
}

// Runs a bash script (to set limits, plant links, read a FIFO around a run of npf).
ToolRun run_script(const std::string& script) {
    static const std::string logs = npf::testing::temporary_folder("publish-logs");
    static int counter = 0;
    const std::string base = logs + "/script" + std::to_string(++counter);
    ToolRun r;
    r.command = "bash -c " + shell_quote(script);
    const std::string full = r.command + " </dev/null >" + shell_quote(base + ".out") + " 2>" + shell_quote(base + ".err");
    const int rc = std::system(full.c_str());
    r.status = (rc != -1 && WIFEXITED(rc)) ? WEXITSTATUS(rc) : -1;
    r.out = read_text(base + ".out");
    r.err = read_text(base + ".err");
    return r;
}

// npf under a 1 KiB file size limit, SIGXFSZ ignored so that writes fail with EFBIG (an ignored
// signal stays ignored across exec).
ToolRun run_limited(const std::vector<std::string>& args) {
    return run_script("trap '' XFSZ; ulimit -f 1; exec " + tool_command(args));
}

const std::string kRecipe = std::string(NPF_SOURCE_DIR) + "/configs/materials/red_plastic.yaml";

std::vector<std::string> convert_args(const std::string& out) {
    return {"convert", kRecipe, "-o", out, "--grid", "16,1,16,32", "--g-grid", "16,1", "--wavelengths", "rgb",
            "--no-predict", "--detail", "none", "--error-pairs", "0", "--quiet", "--threads", "2"};
}
std::vector<std::string> synth_args(const std::string& out) {
    return {"synth", "--diffuse", "0.5", "--wavelengths", "rgb", "--theta", "2", "--ndf", "8", "--vndf", "8",
            "--data", "16", "--quiet", "-o", out};
}
std::vector<std::string> render_args(const std::string& out) {
    return {"render", kRecipe, "-o", out, "--size", "32", "--spp", "1", "--wavelengths", "rgb", "--threads", "2", "--quiet"};
}
std::vector<std::string> render_png_args(const std::string& out, const std::string& png) {
    std::vector<std::string> a = render_args(out);
    a.insert(a.end(), {"--png", png});
    return a;
}

// The inputs edit and display need: a factor texture and a render, made once per process.
struct Inputs {
    std::string texture, scene;
};
const Inputs& inputs() {
    static const Inputs in = [] {
        Inputs i;
        const std::string dir = npf::testing::temporary_folder("publish-inputs");
        i.texture = dir + "/in.exr";
        i.scene = dir + "/scene.exr";
        const ToolRun a = npf::testing::run_tool(convert_args(i.texture));
        const ToolRun b = npf::testing::run_tool(render_args(i.scene));
        EXPECT_EQ(a.status, 0) << describe(a);
        EXPECT_EQ(b.status, 0) << describe(b);
        return i;
    }();
    return in;
}
std::vector<std::string> edit_args(const std::string& out) { return {"edit", inputs().texture, "-o", out, "--rotate", "10"}; }
std::vector<std::string> display_args(const std::string& out) { return {"display", inputs().scene, "-o", out}; }

// Every command that writes a file, with the name its output gets in a test folder.
struct Writer {
    std::string command, file;
    std::function<std::vector<std::string>(const std::string&)> args;
};
const std::vector<Writer>& writers() {
    static const std::vector<Writer> w = {
        {"convert", "out.exr", convert_args}, {"synth", "out.bsdf", synth_args}, {"render", "out.exr", render_args},
        {"edit", "out.exr", edit_args},       {"display", "out.png", display_args},
    };
    return w;
}

// Expects `r` to have failed as a full disk should fail it: status 1, one line on stderr,
// "npf CMD: error: PATH: ..." naming the file and the system's reason.
void expect_one_line_error(const ToolRun& r, const std::string& command, const std::string& path, const std::string& reason) {
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_EQ(lines_of(r.err).size(), 1u) << describe(r);
    EXPECT_EQ(r.err.rfind("npf " + command + ": error: " + path + ": ", 0), 0u) << describe(r);
    EXPECT_TRUE(contains(r.err, reason)) << "expected '" << reason << "'\n" << describe(r);
}

// ================================================================================================
// The library: AtomicOutput and write_file_atomically
// ================================================================================================

TEST(PublishAtomic, ReplacesARegularFileAndLeavesNothingBeside) {
    const std::string dir = npf::testing::temporary_folder("publish");
    const std::string path = dir + "/out.bin";
    npf::write_file_atomically(path, "first", 5);
    ASSERT_TRUE(write_text(dir + "/other", "x"));
    npf::write_file_atomically(path, "second", 6);
    EXPECT_EQ(read_text(path), "second");
    EXPECT_EQ(kind_of(path), mode_t(S_IFREG));
    EXPECT_EQ(folder_entries(dir), (std::vector<std::string>{"other", "out.bin"}));
}

// Item 3 of issue 17: `<out>.tmp-<pid>-<n>` could be predicted, and a link planted there was
// followed. Links are planted at every such name the old scheme would use next.
TEST(PublishAtomic, PlantedLinkAtThePredictableTemporaryNameIsNotFollowed) {
    const std::string dir = npf::testing::temporary_folder("publish");
    const std::string victim = dir + "/victim.txt", out = dir + "/out.bin";
    ASSERT_TRUE(write_text(victim, "precious"));
    long next = 0;
    {
        // The old scheme's counter, read off a temporary name ("...tmp-PID-N"); 0 if not that scheme.
        npf::AtomicOutput probe(dir + "/probe.bin");
        const std::string t = probe.temporary_path();
        const std::string marker = ".tmp-" + std::to_string(::getpid()) + "-";
        const std::size_t at = t.find(marker);
        if (at != std::string::npos) next = std::atol(t.c_str() + at + marker.size()) + 1;
    }
    std::vector<std::string> planted;
    for (long k = 0; k < 8; ++k) {
        for (long n : {k, next + k}) {
            const std::string link = out + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(n);
            if (::symlink(victim.c_str(), link.c_str()) == 0) planted.push_back(link);
        }
    }
    npf::write_file_atomically(out, "new output", 10);
    EXPECT_EQ(read_text(victim), "precious");
    EXPECT_EQ(kind_of(out), mode_t(S_IFREG));
    EXPECT_EQ(read_text(out), "new output");
    for (const std::string& link : planted) EXPECT_EQ(kind_of(link), mode_t(S_IFLNK)) << link;
}

// PUBLISH-NEW-API-BEGIN (tests of functions the old AtomicOutput did not have)

TEST(PublishAtomic, TemporaryIsCreatedExclusivelyUnderARandomName) {
    const std::string dir = npf::testing::temporary_folder("publish");
    const std::string path = dir + "/out.bin";
    {
        npf::AtomicOutput a(path), b(path);
        EXPECT_NE(a.temporary_path(), b.temporary_path());
        for (const npf::AtomicOutput* o : {&a, &b}) {
            const std::string& t = o->temporary_path();
            ASSERT_EQ(t.rfind(path + ".tmp-", 0), 0u) << t;
            const std::string suffix = t.substr(path.size() + 5);
            EXPECT_EQ(suffix.size(), 16u) << t;
            EXPECT_EQ(suffix.find_first_not_of("0123456789abcdef"), std::string::npos) << t;
            EXPECT_EQ(kind_of(t), mode_t(S_IFREG)) << "created when the output is, not when first written";
        }
        EXPECT_FALSE(a.writes_through());
    }
    EXPECT_TRUE(folder_entries(dir).empty()) << "no commit: both temporaries removed";
}

// The temporary is written through its descriptor: a link swapped in for its name later gets
// nothing, and the swap is found before anything is published.
TEST(PublishAtomic, SwappedTemporaryIsNotPublished) {
    const std::string dir = npf::testing::temporary_folder("publish");
    const std::string victim = dir + "/victim.txt", out = dir + "/out.bin";
    ASSERT_TRUE(write_text(victim, "precious"));
    ASSERT_TRUE(write_text(out, "earlier"));
    try {
        npf::AtomicOutput o(out);
        ASSERT_EQ(o.write_at(0, "abc", 3), 3u);
        ASSERT_EQ(::unlink(o.temporary_path().c_str()), 0);
        ASSERT_EQ(::symlink(victim.c_str(), o.temporary_path().c_str()), 0);
        ASSERT_EQ(o.write_at(3, "def", 3), 3u);
        o.commit();
        ADD_FAILURE() << "published a swapped temporary";
    } catch (const npf::Error& e) {
        EXPECT_EQ(e.source(), out);
        EXPECT_TRUE(contains(e.what(), "was replaced while it was written")) << e.what();
    }
    EXPECT_EQ(read_text(victim), "precious");
    EXPECT_EQ(read_text(out), "earlier");
}

TEST(PublishAtomic, WriteErrorsAreKeptAndReported) {
    const std::string dir = npf::testing::temporary_folder("publish");
    const std::string out = dir + "/out.bin";
    ASSERT_TRUE(write_text(out, "earlier"));
    {
        // A file size limit: the write stops short with EFBIG, which commit() reports.
        struct sigaction ignore {}, old_action {};
        ignore.sa_handler = SIG_IGN;
        ::sigaction(SIGXFSZ, &ignore, &old_action);
        struct rlimit old_limit {};
        ::getrlimit(RLIMIT_FSIZE, &old_limit);
        const std::vector<char> big(1 << 16, 'x');
        std::string message;
        {
            npf::AtomicOutput o(out);
            struct rlimit small = old_limit;
            small.rlim_cur = 4096;
            ::setrlimit(RLIMIT_FSIZE, &small);
            const std::size_t written = o.write_at(0, big.data(), big.size());
            ::setrlimit(RLIMIT_FSIZE, &old_limit);
            EXPECT_LT(written, big.size());
            EXPECT_EQ(o.write_at(written, "more", 4), 0u) << "a failed output takes no more writes";
            try {
                o.commit();
            } catch (const npf::Error& e) {
                message = e.what();
            }
        }
        ::sigaction(SIGXFSZ, &old_action, nullptr);
        EXPECT_EQ(message, out + ": cannot write: " + std::strerror(EFBIG));
    }
    EXPECT_EQ(read_text(out), "earlier");
    EXPECT_EQ(folder_entries(dir), std::vector<std::string>{"out.bin"});
}

TEST(PublishAtomic, WhatIsAtTheDestinationDecides) {
    const std::string dir = npf::testing::temporary_folder("publish");
    const auto error_of = [](const std::string& path) -> std::string {
        try {
            npf::write_file_atomically(path, "data", 4);
        } catch (const npf::Error& e) {
            EXPECT_EQ(e.source(), path) << e.what();
            return e.what();
        }
        return "";
    };

    // A folder, a socket, a dangling link, a link to a folder: refused, left as they are.
    const std::string folder = dir + "/folder";
    ASSERT_EQ(::mkdir(folder.c_str(), 0755), 0);
    EXPECT_EQ(error_of(folder), folder + ": is a directory, not a file: cannot move an output over it");
    EXPECT_TRUE(contains(error_of(folder + "/"), "names a folder, not a file"));
    EXPECT_TRUE(folder_entries(folder).empty());

    const std::string socket_path = dir + "/socket";
    const int sock = ::socket(AF_UNIX, SOCK_STREAM, 0);
    ASSERT_GE(sock, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    ASSERT_LT(socket_path.size(), sizeof address.sun_path);
    std::strcpy(address.sun_path, socket_path.c_str());
    ASSERT_EQ(::bind(sock, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
    EXPECT_TRUE(contains(error_of(socket_path), ": is a socket: not written")) << error_of(socket_path);
    EXPECT_EQ(kind_of(socket_path), mode_t(S_IFSOCK));
    ::close(sock);

    const std::string dangling = dir + "/dangling";
    ASSERT_EQ(::symlink("nowhere", dangling.c_str()), 0);
    EXPECT_EQ(error_of(dangling), dangling + ": is a symbolic link to nowhere, which does not exist: not followed "
                                             "(remove the link or create its target)");
    EXPECT_EQ(kind_of(dangling), mode_t(S_IFLNK));
    EXPECT_EQ(kind_of(dir + "/nowhere"), mode_t(0));

    const std::string to_folder = dir + "/to_folder";
    ASSERT_EQ(::symlink("folder", to_folder.c_str()), 0);
    EXPECT_TRUE(contains(error_of(to_folder), "is a symbolic link to a directory, not a file")) << error_of(to_folder);

    // A missing folder, an empty name.
    const std::string missing = dir + "/no/such/folder/x.bin";
    EXPECT_EQ(error_of(missing), missing + ": cannot create output in " + dir + "/no/such/folder: " + std::strerror(ENOENT));
    EXPECT_THROW(npf::write_file_atomically("", "x", 1), npf::Error);

    // A link to a regular file: followed; the link stays, its target gets the output.
    ASSERT_TRUE(write_text(dir + "/target.bin", "old"));
    const std::string link = dir + "/link";
    ASSERT_EQ(::symlink("target.bin", link.c_str()), 0);
    EXPECT_EQ(error_of(link), "");
    EXPECT_EQ(kind_of(link), mode_t(S_IFLNK));
    EXPECT_EQ(read_text(dir + "/target.bin"), "data");

    // A FIFO: written through. Opened here for reading and writing first, so that nothing blocks
    // and a regression (the FIFO replaced by a file) shows as an empty read, not a hang.
    const std::string fifo = dir + "/fifo";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
    const int reader = ::open(fifo.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
    ASSERT_GE(reader, 0);
    EXPECT_EQ(error_of(fifo), "");
    char got[16] = {};
    EXPECT_EQ(::read(reader, got, sizeof got), 4);
    EXPECT_EQ(std::string(got), "data");
    ::close(reader);
    EXPECT_EQ(kind_of(fifo), mode_t(S_IFIFO));

    // Character devices: written through (the null device discards, the full one says why not).
    const std::string null = null_destination(dir);
    if (!null.empty()) {
        EXPECT_EQ(error_of(null), "");
        EXPECT_TRUE(is_char_device(null, 3));
    }
    const std::string full = device_node(dir, "full", 7);
    if (!full.empty()) {
        EXPECT_EQ(error_of(full), full + ": cannot write: " + std::strerror(ENOSPC));
        EXPECT_TRUE(is_char_device(full, 7));
    }
    const std::string block = dir + "/block";
    if (::mknod(block.c_str(), S_IFBLK | 0600, makedev(7, 0)) == 0) {
        EXPECT_TRUE(contains(error_of(block), ": is a block device: not written")) << error_of(block);
        EXPECT_EQ(kind_of(block), mode_t(S_IFBLK));
    }
    EXPECT_FALSE(has_temporaries(dir));
}

TEST(PublishAtomic, CheckOutputPathFailsAsPublishingWouldAndLeavesNothing) {
    const std::string dir = npf::testing::temporary_folder("publish");
    EXPECT_NO_THROW(npf::check_output_path(dir + "/fine.exr"));
    EXPECT_THROW(npf::check_output_path(dir), npf::Error);
    EXPECT_THROW(npf::check_output_path(dir + "/missing/x.exr"), npf::Error);
    EXPECT_TRUE(folder_entries(dir).empty());
}

// PUBLISH-NEW-API-END

// ================================================================================================
// The commands: what is at -o
// ================================================================================================

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

// ================================================================================================
// Faults: a full disk during every writer
// ================================================================================================

// Item 2 of issue 17 under a file size limit (EFBIG, as a full disk gives ENOSPC): each writer
// fails with one line naming its file, and the earlier output is intact.
TEST(PublishFaults, FileSizeLimitKeepsEveryEarlierOutput) {
    const std::string dir = npf::testing::temporary_folder("publish-faults");
    for (const Writer& w : writers()) {
        const std::string out = dir + "/" + w.command + "-" + w.file;
        ASSERT_EQ(npf::testing::run_tool(w.args(out)).status, 0) << w.command;
        const std::string earlier = read_text(out);
        ASSERT_GT(earlier.size(), 2048u) << w.command << ": the output must outgrow the 1 KiB limit";
        const ToolRun r = run_limited(w.args(out));
        expect_one_line_error(r, w.command, out, std::strerror(EFBIG));
        EXPECT_TRUE(read_text(out) == earlier) << w.command << " changed the earlier output";
    }
    // render --png: both earlier files stay.
    const std::string exr = dir + "/both.exr", png = dir + "/both.png";
    ASSERT_EQ(npf::testing::run_tool(render_png_args(exr, png)).status, 0);
    const std::string earlier_exr = read_text(exr), earlier_png = read_text(png);
    ASSERT_GT(earlier_png.size(), 1024u);
    const ToolRun r = run_limited(render_png_args(exr, png));
    expect_one_line_error(r, "render", exr, std::strerror(EFBIG));
    EXPECT_TRUE(read_text(exr) == earlier_exr);
    EXPECT_TRUE(read_text(png) == earlier_png);
    EXPECT_FALSE(has_temporaries(dir));
}

// A small tmpfs, filled: a real full disk (ENOSPC). Needs mount (root); skipped otherwise.
class TmpfsMount {
public:
    explicit TmpfsMount(const std::string& dir) : m_dir(dir) {
        const std::string mount = "mount -t tmpfs -o size=1m npf-publish-test " + shell_quote(dir) + " 2>/dev/null";
        m_mounted = std::system(mount.c_str()) == 0;
    }
    ~TmpfsMount() {
        if (!m_mounted) return;
        const int rc = std::system(("umount " + shell_quote(m_dir)).c_str());
        EXPECT_EQ(rc, 0) << "cannot unmount " << m_dir;
    }
    bool mounted() const { return m_mounted; }

private:
    std::string m_dir;
    bool m_mounted = false;
};

// Fills the file system of `dir` with `dir/filler`, then gives `room` bytes back (whole pages).
void fill_leaving(const std::string& dir, std::size_t room) {
    const std::string filler = dir + "/filler";
    const int fd = ::open(filler.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    ASSERT_GE(fd, 0) << std::strerror(errno);
    const std::vector<char> chunk(1 << 16, 'x');
    std::size_t size = 0;
    int error = 0;
    while (error == 0) {
        const ssize_t n = ::write(fd, chunk.data(), chunk.size());
        if (n < 0 && errno != EINTR) error = errno;
        if (n > 0) size += std::size_t(n);
    }
    EXPECT_EQ(error, ENOSPC);
    const std::size_t page = 4096, keep = size > room ? (size - room) / page * page : 0;
    EXPECT_EQ(::ftruncate(fd, off_t(keep)), 0);
    ::close(fd);
    struct statvfs vfs {};
    ASSERT_EQ(::statvfs(dir.c_str(), &vfs), 0);
    EXPECT_LT(std::size_t(vfs.f_bavail) * vfs.f_bsize, room + 2 * page);
}

TEST(PublishFaults, FullTmpfsKeepsEveryEarlierOutput) {
    const std::string dir = npf::testing::temporary_folder("publish-tmpfs");
    const TmpfsMount mount(dir);
    if (!mount.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
    const std::string filler = dir + "/filler";
    for (const Writer& w : writers()) {
        const std::string out = dir + "/" + w.command + "-" + w.file;
        ASSERT_EQ(npf::testing::run_tool(w.args(out)).status, 0) << w.command;
        const std::string earlier = read_text(out);
        fill_leaving(dir, 0);
        const ToolRun r = npf::testing::run_tool(w.args(out));
        expect_one_line_error(r, w.command, out, std::strerror(ENOSPC));
        EXPECT_TRUE(read_text(out) == earlier) << w.command << " changed the earlier output";
        ::unlink(filler.c_str());
    }
    // render --png with room for the EXR but not the PNG: the EXR is complete, the PNG fails,
    // and neither earlier file changes.
    const std::string exr = dir + "/both.exr", png = dir + "/both.png";
    ASSERT_EQ(npf::testing::run_tool(render_png_args(exr, png)).status, 0);
    const std::string earlier_exr = read_text(exr), earlier_png = read_text(png);
    const std::size_t room = (earlier_exr.size() + 4095) / 4096 * 4096;
    ASSERT_GT(room - earlier_exr.size(), 256u) << "the new EXR (its header varies by a few bytes) must fit";
    fill_leaving(dir, room);
    const ToolRun r = npf::testing::run_tool(render_png_args(exr, png));
    expect_one_line_error(r, "render", png, std::strerror(ENOSPC));
    EXPECT_TRUE(read_text(exr) == earlier_exr) << "the earlier EXR changed";
    EXPECT_TRUE(read_text(png) == earlier_png) << "the earlier PNG changed";
    ::unlink(filler.c_str());
    EXPECT_FALSE(has_temporaries(dir));
}

}  // namespace
