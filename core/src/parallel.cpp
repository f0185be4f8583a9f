#include <npf/core/parallel.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace npf {

namespace {

// Constant-initialised, so usable from other static initialisers. A call copies the pointer once
// and keeps that executor to its end, so replacing it never pulls one out from under a call.
std::mutex g_executor_mutex;
std::shared_ptr<const ParallelExecutor> g_executor;

std::shared_ptr<const ParallelExecutor> current_executor() {
    const std::lock_guard<std::mutex> lock(g_executor_mutex);
    return g_executor;
}

int resolve_threads(int requested, const ParallelExecutor* executor) {
    if (requested > 0) return requested;
    if (executor && executor->default_threads > 0) return executor->default_threads;
    return int(std::max(1u, std::thread::hardware_concurrency()));
}

// npf's own executor: task 0 on the calling thread, the others on threads started for this call
// only, so that a nested call never waits for a thread that waits for it. A thread the system
// refuses is no failure: the calling thread runs that task afterwards (npf's tasks all drain one
// queue, so by then it finds nothing left to do).
void run_on_own_threads(std::size_t tasks, const std::function<void(std::size_t)>& task) {
    std::vector<std::thread> threads;
    threads.reserve(tasks - 1);
    std::size_t started = 1;
    for (; started < tasks; ++started) {
        try {
            threads.emplace_back(task, started);
        } catch (const std::system_error&) {
            break;
        }
    }
    task(0);
    for (std::size_t t = started; t < tasks; ++t) task(t);
    for (std::thread& thread : threads) thread.join();
}

}  // namespace

int thread_count(int requested) {
    return resolve_threads(requested, requested > 0 ? nullptr : current_executor().get());
}

void parallel_for(std::size_t count, const std::function<void(std::size_t)>& body, int max_threads,
                  const std::function<void(double)>& progress) {
    const std::shared_ptr<const ParallelExecutor> executor = current_executor();
    const std::size_t tasks = std::min(count, std::size_t(resolve_threads(max_threads, executor.get())));

    std::atomic<std::size_t> next{0}, done{0};
    std::atomic<bool> failed{false};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    const std::thread::id caller = std::this_thread::get_id();
    // Every task takes items from one counter until none are left: the items' order and split do
    // not depend on which task or thread runs them. Nothing may escape into the executor.
    auto drain = [&](std::size_t) {
        const bool reports = progress && std::this_thread::get_id() == caller;
        for (std::size_t i; !failed.load(std::memory_order_relaxed) && (i = next.fetch_add(1)) < count;) {
            try {
                body(i);
                const std::size_t finished = done.fetch_add(1) + 1;
                if (reports) progress(double(finished) / double(count));
            } catch (...) {
                const std::lock_guard<std::mutex> lock(failure_mutex);
                if (!failure) failure = std::current_exception();
                failed = true;
            }
        }
    };
    if (tasks <= 1) drain(0);  // one thread (or nothing to do): no executor, no thread started
    else if (executor && executor->run) executor->run(tasks, drain);
    else run_on_own_threads(tasks, drain);

    if (failure) std::rethrow_exception(failure);
    if (progress) progress(1.0);
}

void parallel_slices(std::size_t count, std::size_t slices,
                     const std::function<void(std::size_t, std::size_t, std::size_t)>& body, int max_threads) {
    if (slices == 0) {
        if (count == 0) return;
        throw std::invalid_argument("npf::parallel_slices: no slices for " + std::to_string(count) + " items");
    }
    parallel_for(
        slices, [&](std::size_t s) { body(s, count * s / slices, count * (s + 1) / slices); }, max_threads);
}

void set_parallel_executor(ParallelExecutor executor) {
    auto installed = std::make_shared<const ParallelExecutor>(std::move(executor));
    const std::lock_guard<std::mutex> lock(g_executor_mutex);
    g_executor = std::move(installed);
}

}  // namespace npf
