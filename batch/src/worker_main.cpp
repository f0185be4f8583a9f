// The worker process's side (`npf batch --worker JOB`, docs/batch.md "Failure isolation"): one
// material converted into the stage folder under the job's memory limit, its answer and the list
// of its finished files left for the parent.
#include "worker_job.h"

#include <npf/batch/runner.h>
#include <npf/core/error.h>
#include <npf/core/text.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

namespace npf::batch {

namespace {

// RLIMIT_DATA (heap and private writable mappings: what a material's tables take), not
// RLIMIT_AS, which also counts the libraries' code and every thread's 64 MiB malloc arena
// reservation, so that its value would depend on the thread count. Set before any material is
// read; an allocation past it fails (std::bad_alloc in C++ code).
void limit_memory(std::uint64_t bytes, const std::string& job_path) {
    struct rlimit limit {};
    ::getrlimit(RLIMIT_DATA, &limit);
    const rlim_t want = rlim_t(bytes);
    limit.rlim_cur = limit.rlim_max == RLIM_INFINITY ? want : std::min(want, limit.rlim_max);
    if (::setrlimit(RLIMIT_DATA, &limit) != 0) throw Error(job_path, std::string("cannot set the memory limit: ") + std::strerror(errno));
}

// The list of finished files, (staged name, final path) pairs.
std::string moves_text(const std::vector<std::pair<std::string, std::string>>& moves) {
    YAML::Emitter out;
    out << YAML::BeginSeq;
    for (const auto& [name, to] : moves)
        out << YAML::Flow << YAML::BeginSeq << YAML::DoubleQuoted << name << YAML::DoubleQuoted << to << YAML::EndSeq;
    out << YAML::EndSeq;
    return std::string(out.c_str()) + "\n";
}

}  // namespace

int run_batch_worker(const std::string& job_path, const MaterialHook& before_material) {
    // Dies with the batch (kill -9 included) rather than finishing on its own; the parent's pid
    // in the job catches a parent that died before this line.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    try {
        const detail::WorkerJob w = detail::read_worker_job(job_path);
        if (long(::getppid()) != w.parent) {
            std::fprintf(stderr, "npf batch --worker: the batch that started this worker has ended\n");
            return 3;
        }
        detail::MaterialContext ctx;
        ctx.in_worker = true;
        ctx.stage = &w.stage;
        ctx.force = w.force;
        ctx.shard = w.shard;
        ctx.memory_limit = w.memory_limit;
        ctx.before_material = before_material;
        if (ctx.memory_limit > 0) limit_memory(ctx.memory_limit, job_path);
        BatchSummary answer;
        answer.config = job_path;
        answer.materials.push_back(detail::process_material(w.job, ctx));
        // The list of finished files first: the answer's presence says both are complete.
        w.stage.write_new_file(w.moves, moves_text(ctx.moves));
        w.stage.write_new_file(w.result, summary_json(answer));
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "npf batch --worker: %s\n", printable(e.what()).c_str());
        return 3;
    }
}

}  // namespace npf::batch
