#include "run_tool.h"

#include "synthetic_rgl.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <sys/wait.h>

namespace npf::testing {

namespace {

// Where the redirected streams go: one folder per test process, removed at exit.
const std::string& log_folder() {
    static const std::string dir = temporary_folder("tool_runs");
    return dir;
}

}  // namespace

std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream os;
    os << in.rdbuf();
    return os.str();
}

bool write_text(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    return !out.fail();
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::vector<std::string> folder_entries(const std::string& dir) {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

ToolRun run_tool(const std::vector<std::string>& args, const ToolRunOptions& options) {
    static int counter = 0;
    const std::string base = log_folder() + "/run" + std::to_string(++counter);
    std::string in_path = "/dev/null";
    if (options.stdin_text) {
        in_path = base + ".in";
        write_text(in_path, *options.stdin_text);
    }
    ToolRun r;
    r.command = shell_quote(NPF_TOOL_PATH);
    for (const std::string& a : args) r.command += " " + shell_quote(a);
    // `exec` keeps the tool the shell's direct replacement, so that a crash shows as one.
    if (!options.working_dir.empty()) r.command = "cd " + shell_quote(options.working_dir) + " && exec " + r.command;
    const std::string full = r.command + " <" + shell_quote(in_path) + " >" + shell_quote(base + ".out") + " 2>" +
                             shell_quote(base + ".err");
    const int rc = std::system(full.c_str());
    r.status = (rc != -1 && WIFEXITED(rc)) ? WEXITSTATUS(rc) : -1;
    r.out = read_text(base + ".out");
    r.err = read_text(base + ".err");
    return r;
}

std::string describe(const ToolRun& r) {
    return "command: " + r.command + "\nstatus: " + std::to_string(r.status) + "\nstdout:\n" + r.out + "\nstderr:\n" +
           r.err;
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream is(text);
    for (std::string line; std::getline(is, line);) lines.push_back(line);
    return lines;
}

bool has_line(const std::string& text, const std::string& line) {
    for (const std::string& l : lines_of(text)) {
        if (l == line) return true;
    }
    return false;
}

}  // namespace npf::testing
