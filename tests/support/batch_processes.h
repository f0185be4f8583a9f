// `npf` as a process of its own for the batch's hostile tests: started in the background with
// its own environment, limits or user, waited for with a deadline, its worker processes found
// by their command lines; and what a batch left behind (statuses, reasons, temporaries).
#pragma once

#include "run_tool.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <sys/types.h>

namespace npf::testing {

// A small synthetic RGL material (5 theta, 16/8/8 grids) of roughness `alpha`.
void write_test_material(const std::string& path, float alpha);
// A temporary folder with the named materials in `in/`.
std::string material_library(const std::string& tag, const std::vector<std::string>& names);

struct RunOptions {
    std::vector<std::string> env;     // NAME=VALUE, for this run only
    bool unprivileged = false;         // as nobody when root (who writes anywhere)
    double deadline_s = 120;           // then killed
    std::uint64_t memory_cap = 0;      // RLIMIT_AS, bytes; 0: none
};

// `npf args...` started in the background, its output into `log` + ".out" / ".err".
pid_t start_tool(const std::vector<std::string>& args, const std::string& log, const RunOptions& o = {});
// Waits for `pid` at most `deadline_s` (then kills it); its wait status, or -1 when it was killed
// at the deadline.
int wait_for(pid_t pid, double deadline_s);
// `npf args...` run to its end (or its deadline).
ToolRun run_npf(const std::vector<std::string>& args, const RunOptions& o = {});

// The pid of a live (not zombie) process whose command line holds `part`; 0 when none.
pid_t process_with(const std::string& part);
// Waits (at most 30 s) for the worker of material `name` of the shard-0-of-1 stage under `out`.
pid_t wait_for_worker(const std::string& out, const std::string& name);

// Every entry under `dir` that is not under `skip` (a path relative to it), by kind and content:
// links are listed, never followed.
std::map<std::string, std::string> tree_of(const std::string& dir, const std::string& skip = "");
// Material name -> status name, of a summary file.
std::map<std::string, std::string> statuses(const std::string& summary);
// A material's reason in a summary file.
std::string reason_of(const std::string& summary, const std::string& name);
// Whether a temporary file (".tmp-") is anywhere under `dir`.
bool has_temporaries(const std::string& dir);

}  // namespace npf::testing
