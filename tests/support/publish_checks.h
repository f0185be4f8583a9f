// Shared by the publishing tests (test_publish*.cpp): the kind of node at a path, private
// device nodes, npf run from a bash script (limits, planted links), and every writer's command
// line with the name its output gets.
#pragma once

#include "run_tool.h"
#include "synthetic_rgl.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

namespace npf::testing::publish {

// Brought to the tests by their `using namespace`.
using npf::testing::contains, npf::testing::describe, npf::testing::folder_entries, npf::testing::lines_of,
      npf::testing::read_text, npf::testing::shell_quote, npf::testing::ToolRun, npf::testing::write_text;

inline mode_t kind_of(const std::string& path) {
    struct stat st {};
    return ::lstat(path.c_str(), &st) == 0 ? (st.st_mode & S_IFMT) : 0;
}

inline bool is_char_device(const std::string& path, unsigned minor) {
    struct stat st {};
    return ::lstat(path.c_str(), &st) == 0 && S_ISCHR(st.st_mode) && st.st_rdev == makedev(1, minor);
}

// A private node for the memory device `minor` (3: null, 7: full) in `dir`; "" where nodes cannot
// be made or opened (not root, a nodev mount).
inline std::string device_node(const std::string& dir, const std::string& name, unsigned minor) {
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
inline std::string null_destination(const std::string& dir) {
    const std::string node = device_node(dir, "null", 3);
    if (!node.empty()) return node;
    return ::geteuid() != 0 ? "/dev/null" : "";
}

inline bool has_temporaries(const std::string& dir) {
    for (const std::string& name : folder_entries(dir))
        if (contains(name, ".tmp-")) return true;
    return false;
}

inline std::string tool_command(const std::vector<std::string>& args) {
    std::string c = shell_quote(NPF_TOOL_PATH);
    for (const std::string& a : args) c += " " + shell_quote(a);
    return c;
}

// Runs a bash script (to set limits, plant links, read a FIFO around a run of npf).
inline ToolRun run_script(const std::string& script) {
    static const std::string logs = temporary_folder("publish-logs");
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
inline ToolRun run_limited(const std::vector<std::string>& args) {
    return run_script("trap '' XFSZ; ulimit -f 1; exec " + tool_command(args));
}

inline const std::string kRecipe = std::string(NPF_SOURCE_DIR) + "/configs/materials/red_plastic.yaml";

inline std::vector<std::string> convert_args(const std::string& out) {
    return {"convert", kRecipe, "-o", out, "--grid", "16,1,16,32", "--g-grid", "16,1", "--wavelengths", "rgb",
            "--no-predict", "--detail", "none", "--error-pairs", "0", "--quiet", "--threads", "2"};
}
inline std::vector<std::string> synth_args(const std::string& out) {
    return {"synth", "--diffuse", "0.5", "--wavelengths", "rgb", "--theta", "2", "--ndf", "8", "--vndf", "8",
            "--data", "16", "--quiet", "-o", out};
}
inline std::vector<std::string> render_args(const std::string& out) {
    return {"render", kRecipe, "-o", out, "--size", "32", "--spp", "1", "--wavelengths", "rgb", "--threads", "2", "--quiet"};
}
inline std::vector<std::string> render_png_args(const std::string& out, const std::string& png) {
    std::vector<std::string> a = render_args(out);
    a.insert(a.end(), {"--png", png});
    return a;
}

// The inputs edit and display need: a factor texture and a render, made once per process.
struct Inputs {
    std::string texture, scene;
};
inline const Inputs& inputs() {
    static const Inputs in = [] {
        Inputs i;
        const std::string dir = temporary_folder("publish-inputs");
        i.texture = dir + "/in.exr";
        i.scene = dir + "/scene.exr";
        const ToolRun a = run_tool(convert_args(i.texture));
        const ToolRun b = run_tool(render_args(i.scene));
        EXPECT_EQ(a.status, 0) << describe(a);
        EXPECT_EQ(b.status, 0) << describe(b);
        return i;
    }();
    return in;
}
inline std::vector<std::string> edit_args(const std::string& out) { return {"edit", inputs().texture, "-o", out, "--rotate", "10"}; }
inline std::vector<std::string> display_args(const std::string& out) { return {"display", inputs().scene, "-o", out}; }

// Every command that writes a file, with the name its output gets in a test folder.
struct Writer {
    std::string command, file;
    std::function<std::vector<std::string>(const std::string&)> args;
};
inline const std::vector<Writer>& writers() {
    static const std::vector<Writer> w = {
        {"convert", "out.exr", convert_args}, {"synth", "out.bsdf", synth_args}, {"render", "out.exr", render_args},
        {"edit", "out.exr", edit_args},       {"display", "out.png", display_args},
    };
    return w;
}

// Expects `r` to have failed as a full disk should fail it: status 1, one line on stderr,
// "npf CMD: error: PATH: ..." naming the file and the system's reason.
inline void expect_one_line_error(const ToolRun& r, const std::string& command, const std::string& path, const std::string& reason) {
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_EQ(lines_of(r.err).size(), 1u) << describe(r);
    EXPECT_EQ(r.err.rfind("npf " + command + ": error: " + path + ": ", 0), 0u) << describe(r);
    EXPECT_TRUE(contains(r.err, reason)) << "expected '" << reason << "'\n" << describe(r);
}

}  // namespace npf::testing::publish
