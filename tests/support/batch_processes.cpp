#include "batch_processes.h"

#include "synthetic_rgl.h"

#include <npf/batch/summary.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <thread>

#include <fcntl.h>
#include <grp.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace npf::testing {

namespace fs = std::filesystem;
namespace batch = npf::batch;

void write_test_material(const std::string& path, float alpha) {
    npf::testing::SyntheticRglSpec s;
    s.theta_count = 5;
    s.ndf_size = 16;
    s.vndf_size = 8;
    s.data_size = 8;
    s.alpha_x = s.alpha_y = alpha;
    npf::testing::write_synthetic_rgl(s, path);
}

// A folder with the named materials in `in/`.
std::string material_library(const std::string& tag, const std::vector<std::string>& names) {
    const std::string dir = npf::testing::temporary_folder(tag);
    fs::create_directories(dir + "/in");
    for (std::size_t i = 0; i < names.size(); ++i) write_test_material(dir + "/in/" + names[i] + ".bsdf", 0.2f + 0.1f * float(i));
    return dir;
}

// Every entry under `dir` that is not under `skip` (a path relative to it), by kind and content:
// links are listed, never followed.
std::map<std::string, std::string> tree_of(const std::string& dir, const std::string& skip) {
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

// `npf args...` started in the background, its output into `log` + ".out" / ".err".
pid_t start_tool(const std::vector<std::string>& args, const std::string& log, const RunOptions& o) {
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
ToolRun run_npf(const std::vector<std::string>& args, const RunOptions& o) {
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

}  // namespace npf::testing
