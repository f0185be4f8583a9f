// Running one material's worker process (`npf batch --worker JOB`, docs/batch.md "Failure
// isolation"): spawned with posix_spawn (safe in a multithreaded caller), waited for with a wall
// time limit, and its end classified. Private to npf_batch.
#pragma once

#include <csignal>
#include <string>
#include <vector>

namespace npf::batch::detail {

struct WorkerEnd {
    std::string start_error;  // non-empty: it could not be started (strerror)
    bool timed_out = false;   // killed (SIGKILL) by us at the time limit
    bool stopped = false;     // killed (SIGKILL) by us on a stop request
    bool exited = false;      // exited normally with exit_code
    int exit_code = 0;
    int signal = 0;           // > 0: ended by this signal
    double peak_resident_bytes = 0.0;
    bool status_lost = false;  // the status could not be collected (SIGCHLD ignored by the caller)
};

// Runs `executable args...` with standard input /dev/null and standard output and error into
// the file open at `log_fd` (made by the caller, never through a link), and waits for it; at
// `time_limit_s` (> 0), or once `*stop` is non-zero, it is killed. The child gets this process's
// environment and an empty signal mask.
WorkerEnd run_worker_process(const std::string& executable, const std::vector<std::string>& args, int log_fd,
                             double time_limit_s, const volatile std::sig_atomic_t* stop = nullptr);

// "signal 11 (segmentation fault)".
std::string signal_text(int signal);

// The last non-empty line of the (log) file open at `fd`, at most `limit` characters; "" when none.
std::string last_line(int fd, std::size_t limit = 300);

}  // namespace npf::batch::detail
