#include "worker_process.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace npf::batch::detail {

namespace {

// A descriptor that becomes readable when the process ends (Linux 5.3+), so that waiting costs
// no polling delay; -1 where unavailable (then a short sleep loop).
int open_pidfd(pid_t pid) {
#ifdef SYS_pidfd_open
    return int(::syscall(SYS_pidfd_open, pid, 0));
#else
    (void)pid;
    return -1;
#endif
}

}  // namespace

WorkerEnd run_worker_process(const std::string& executable, const std::vector<std::string>& args, int log_fd,
                             double time_limit_s, const volatile std::sig_atomic_t* stop) {
    WorkerEnd end;
    std::vector<std::string> argv_text;
    argv_text.push_back(executable);
    argv_text.insert(argv_text.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : argv_text) argv.push_back(a.data());
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawnattr_t attr;
    ::posix_spawn_file_actions_init(&actions);
    ::posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    ::posix_spawn_file_actions_adddup2(&actions, log_fd, 1);
    ::posix_spawn_file_actions_adddup2(&actions, 1, 2);
    ::posix_spawnattr_init(&attr);
    sigset_t none;
    sigemptyset(&none);
    ::posix_spawnattr_setsigmask(&attr, &none);  // a caller's thread may block signals the worker needs
    ::posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK);
    pid_t pid = -1;
    const int rc = ::posix_spawn(&pid, executable.c_str(), &actions, &attr, argv.data(), environ);
    ::posix_spawn_file_actions_destroy(&actions);
    ::posix_spawnattr_destroy(&attr);
    if (rc != 0) {
        end.start_error = std::strerror(rc);
        return end;
    }

    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(time_limit_s));
    const int pidfd = open_pidfd(pid);
    int status = 0;
    struct rusage usage {};
    for (;;) {
        const pid_t got = ::wait4(pid, &status, WNOHANG, &usage);
        if (got == pid) break;
        if (got < 0 && errno != EINTR) {
            end.status_lost = true;  // ECHILD: reaped elsewhere (SIGCHLD ignored)
            break;
        }
        if (stop && *stop) {
            ::kill(pid, SIGKILL);
            while (::wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
            }
            end.stopped = true;
            break;
        }
        // Short enough that a stop request (whose signal may land just before poll) is seen soon.
        int wait_ms = stop ? 200 : 1000;
        if (time_limit_s > 0) {
            const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
            if (left <= 0) {
                ::kill(pid, SIGKILL);
                while (::wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
                }
                end.timed_out = true;
                break;
            }
            wait_ms = int(std::min(double(wait_ms), left * 1000.0 + 1.0));
        }
        if (pidfd >= 0) {
            struct pollfd p {pidfd, POLLIN, 0};
            ::poll(&p, 1, wait_ms);
        } else {
            ::poll(nullptr, 0, std::min(wait_ms, 5));
        }
    }
    if (pidfd >= 0) ::close(pidfd);
    end.peak_resident_bytes = double(usage.ru_maxrss) * 1024.0;
    if (end.status_lost || end.timed_out || end.stopped) return end;
    if (WIFEXITED(status)) {
        end.exited = true;
        end.exit_code = WEXITSTATUS(status);
    } else if (WIFSIGNALED(status)) {
        end.signal = WTERMSIG(status);
    }
    return end;
}

std::string signal_text(int signal) {
    const char* name = ::strsignal(signal);
    std::string text = name ? name : "unknown signal";
    for (char& c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
    return "signal " + std::to_string(signal) + " (" + text + ")";
}

std::string last_line(int fd, std::size_t limit) {
    struct stat st {};
    if (fd < 0 || ::fstat(fd, &st) != 0) return "";
    const off_t from = std::max<off_t>(0, st.st_size - 8192);
    std::string text(std::size_t(st.st_size - from), '\0');
    ssize_t got;
    do {
        got = ::pread(fd, text.data(), text.size(), from);
    } while (got < 0 && errno == EINTR);
    text.resize(got > 0 ? std::size_t(got) : 0);
    std::string line;
    std::size_t end = text.size();
    while (end > 0) {
        const std::size_t start = text.rfind('\n', end - 1);
        const std::size_t b = start == std::string::npos ? 0 : start + 1;
        line = text.substr(b, end - b);
        line.erase(std::remove(line.begin(), line.end(), '\r'), line.end());
        if (line.find_first_not_of(" \t") != std::string::npos) break;
        line.clear();
        if (start == std::string::npos) break;
        end = start;
    }
    if (line.size() > limit) line = line.substr(0, limit) + "...";
    return line;
}

}  // namespace npf::batch::detail
