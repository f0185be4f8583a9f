// The one way npf runs work on several threads (issue 18): parallel_for over independent items,
// and parallel_slices for work whose split must not depend on the thread count.
//
// Backend: npf's own std::threads, started per call (as the pools this replaced did; a call on
// one thread starts none), unless a host installs its executor (set_parallel_executor). Not
// OpenImageIO's pool, nor TBB, because
//   - npf_core has no third-party dependency, and a loop helper should not be what adds one;
//     OpenImageIO stays with the libraries that read and write images;
//   - what the callers need is fixed here, whatever runs the tasks: the split into items or slices
//     is decided before any thread starts (fits stay bit-identical across thread counts), at most
//     `max_threads` threads run items at a time (the executor is only ever asked for that many
//     tasks), and the first exception is caught here and rethrown after every task returned;
//   - a host renderer steers npf through the hook with a few lines over the pool it already has
//     (OIIO::parallel_for over the tasks, a tbb::task_group, ...), so npf's work shares its threads
//     and its limit instead of adding a pool of its own.
//
// Nested calls (parallel_for inside an item of parallel_for) cannot deadlock with the default
// executor: every call starts threads of its own and waits only for them. A host executor must
// allow the same (OpenImageIO's pool runs nested calls on the calling thread; TBB's tasks nest).
#pragma once

#include <cstddef>
#include <functional>

namespace npf {

// The threads a call asking for `requested` gets: `requested` when > 0; otherwise the installed
// executor's default, or else std::thread::hardware_concurrency(); never less than 1.
int thread_count(int requested);

// Runs body(i) once for every i in [0, count) on at most thread_count(max_threads) threads, the
// calling thread among them (with the default executor; one thread: the caller alone, no
// executor), handing out items one at a time in ascending order; returns when every started item
// has returned. Outputs must depend only on i (per-item slots, reduced serially after) for
// results not to depend on the threads.
//
// The first exception an item throws (first in time) is rethrown here after all threads have
// finished; items not yet started when it was thrown are skipped.
//
// `progress`, if set, is called from the calling thread only: with the fraction of items done
// after each item that thread finishes (a host executor that never runs a task on the calling
// thread gives none of these), and with 1 after all finished without an exception.
void parallel_for(std::size_t count, const std::function<void(std::size_t index)>& body, int max_threads = 0,
                  const std::function<void(double fraction)>& progress = nullptr);

// Cuts [0, count) into `slices` contiguous slices, slice s being
// [count * s / slices, count * (s + 1) / slices) (some empty when slices > count), and runs
// body(s, begin, end) once for each through parallel_for. The boundaries depend only on `count`
// and `slices`, never on the threads: a caller with per-slice partial sums fixes `slices` and
// adds the partials in slice order to get the same bits on any number of threads.
void parallel_slices(std::size_t count, std::size_t slices,
                     const std::function<void(std::size_t slice, std::size_t begin, std::size_t end)>& body,
                     int max_threads = 0);

// A host's way to run npf's parallel work on its own threads. run(tasks, task) must call
// task(t) exactly once for every t in [0, tasks), on any threads in any order, concurrently or
// not, and return only after all have returned; it must not throw. task never throws, and
// npf asks for no more tasks than the threads a call may use, so npf's thread limit holds on
// any executor. run must accept being called from inside one of its own tasks (nested use)
// without deadlock. An empty run: npf's own threads. `default_threads` is what thread_count(0)
// answers (0: the hardware's), e.g. a host's thread limit.
//
// Example over OpenImageIO's pool (steered by OIIO::attribute("threads", n)):
//     npf::ParallelExecutor e;
//     e.run = [](std::size_t tasks, const std::function<void(std::size_t)>& task) {
//         OIIO::parallel_for(uint64_t(0), uint64_t(tasks), [&](uint64_t t) { task(t); },
//                            OIIO::paropt(int(tasks)).minitems(1));
//     };
//     e.default_threads = OIIO::get_int_attribute("threads");
//     npf::set_parallel_executor(std::move(e));
struct ParallelExecutor {
    std::function<void(std::size_t tasks, const std::function<void(std::size_t task)>& task)> run;
    int default_threads = 0;
};

// Installs `executor` for every later call, process-wide; ParallelExecutor{} restores the
// defaults. Calls already running finish on the executor they started with.
void set_parallel_executor(ParallelExecutor executor);

}  // namespace npf
