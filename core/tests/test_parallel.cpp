// Tests of npf::parallel_for and npf::parallel_slices (npf/core/parallel.h): every item once,
// exceptions, nested calls, the thread limit, slice boundaries that do not depend on the threads,
// progress, and a host's executor (OpenImageIO's pool, as the header's example installs it).
#include <npf/core/parallel.h>

#include <OpenImageIO/parallel.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <functional>
#include <future>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

namespace {

using namespace std::chrono_literals;

// Runs `f` on a thread of its own and fails (instead of hanging the suite) when it has not
// returned within `limit`: a deadlocked call leaves that thread behind, detached.
void finishes_within(std::chrono::seconds limit, std::function<void()> f) {
    auto done = std::make_shared<std::promise<void>>();
    std::future<void> finished = done->get_future();
    std::thread([f = std::move(f), done] {
        try {
            f();
            done->set_value();
        } catch (...) {
            done->set_exception(std::current_exception());
        }
    }).detach();
    ASSERT_EQ(finished.wait_for(limit), std::future_status::ready) << "did not finish: deadlock?";
    finished.get();
}

// Restores npf's own threads when a test that installs an executor ends, even by a failure.
struct ExecutorGuard {
    explicit ExecutorGuard(npf::ParallelExecutor e) { npf::set_parallel_executor(std::move(e)); }
    ~ExecutorGuard() { npf::set_parallel_executor({}); }
};

// The header's example: npf's tasks on OpenImageIO's pool.
npf::ParallelExecutor oiio_executor() {
    npf::ParallelExecutor e;
    e.run = [](std::size_t tasks, const std::function<void(std::size_t)>& task) {
        OIIO::parallel_for(uint64_t(0), uint64_t(tasks), [&](uint64_t t) { task(std::size_t(t)); },
                           OIIO::paropt(int(tasks)).minitems(1));
    };
    return e;
}

// What the tests below check on each executor.
void every_index_once(int max_threads) {
    for (std::size_t count : {std::size_t(0), std::size_t(1), std::size_t(7), std::size_t(10007)}) {
        std::vector<std::atomic<int>> visits(count);
        for (auto& v : visits) v = 0;
        npf::parallel_for(count, [&](std::size_t i) { ++visits[i]; }, max_threads);
        for (std::size_t i = 0; i < count; ++i) ASSERT_EQ(visits[i].load(), 1) << "index " << i << " of " << count;
    }
}

std::size_t nested_sum(int threads) {
    std::atomic<std::size_t> sum{0};
    npf::parallel_for(8, [&](std::size_t i) {
        npf::parallel_for(100, [&](std::size_t j) {
            npf::parallel_for(3, [&](std::size_t k) { sum += i * 1000 + j * 10 + k; }, threads);
        }, threads);
    }, threads);
    return sum;
}

std::size_t expected_nested_sum() {
    std::size_t s = 0;
    for (std::size_t i = 0; i < 8; ++i)
        for (std::size_t j = 0; j < 100; ++j)
            for (std::size_t k = 0; k < 3; ++k) s += i * 1000 + j * 10 + k;
    return s;
}

}  // namespace

TEST(Parallel, EveryIndexExactlyOnce) {
    for (int threads : {1, 2, 3, 8, 0}) every_index_once(threads);
}

TEST(Parallel, FirstExceptionRethrownAfterEveryItemReturned) {
    const std::thread::id caller = std::this_thread::get_id();
    std::atomic<int> in_flight{0};
    std::atomic<int> started{0};
    try {
        npf::parallel_for(2000, [&](std::size_t i) {
            ++started;
            if (i == 3) throw std::runtime_error("item 3");
            ++in_flight;
            // The other threads' items outlast the caller's: returning before them would show.
            std::this_thread::sleep_for(std::this_thread::get_id() == caller ? 1ms : 20ms);
            --in_flight;
        }, 4);
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "item 3");
        EXPECT_EQ(in_flight.load(), 0) << "returned while items still ran";
    }
    // Items not started when it was thrown were skipped (all of them would take seconds).
    EXPECT_LT(started.load(), 2000);
}

TEST(Parallel, OneExceptionOfManyAndItsType) {
    try {
        npf::parallel_for(64, [](std::size_t i) { throw std::out_of_range("item " + std::to_string(i)); }, 4);
        FAIL() << "no exception";
    } catch (const std::out_of_range& e) {
        EXPECT_EQ(std::strncmp(e.what(), "item ", 5), 0) << e.what();
    }
    // On one thread items run in order: the first to throw is item 0, and nothing runs after it.
    std::vector<std::size_t> ran;
    try {
        npf::parallel_for(10, [&](std::size_t i) {
            ran.push_back(i);
            if (i >= 2) throw std::runtime_error("item " + std::to_string(i));
        }, 1);
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "item 2");
    }
    EXPECT_EQ(ran, (std::vector<std::size_t>{0, 1, 2}));
}

TEST(Parallel, ExceptionsFromSlicesAndNestedCallsPropagate) {
    EXPECT_THROW(npf::parallel_slices(100, 4, [](std::size_t s, std::size_t, std::size_t) {
        if (s == 2) throw std::logic_error("slice 2");
    }, 4), std::logic_error);
    EXPECT_THROW(npf::parallel_for(4, [](std::size_t) {
        npf::parallel_for(4, [](std::size_t j) {
            if (j == 1) throw std::runtime_error("inner");
        }, 2);
    }, 2), std::runtime_error);
    EXPECT_THROW(npf::parallel_slices(5, 0, [](std::size_t, std::size_t, std::size_t) {}), std::invalid_argument);
}

TEST(Parallel, NestedCallsAndCallsFromOtherThreadsDoNotDeadlock) {
    const std::size_t expected = expected_nested_sum();
    finishes_within(60s, [&] {
        for (int threads : {1, 2, 4, 0}) EXPECT_EQ(nested_sum(threads), expected) << threads << " threads";
    });
    // From several host threads at once, each nesting.
    finishes_within(60s, [&] {
        std::vector<std::thread> hosts;
        std::vector<std::size_t> sums(3);
        for (std::size_t h = 0; h < sums.size(); ++h) hosts.emplace_back([&, h] { sums[h] = nested_sum(2); });
        for (std::thread& t : hosts) t.join();
        for (std::size_t s : sums) EXPECT_EQ(s, expected);
    });
}

TEST(Parallel, ThreadLimitHolds) {
    for (int cap : {1, 2, 3}) {
        std::mutex m;
        std::set<std::thread::id> ids;
        std::atomic<int> in_flight{0}, most{0};
        npf::parallel_for(48, [&](std::size_t) {
            const int now = ++in_flight;
            for (int seen = most.load(); now > seen && !most.compare_exchange_weak(seen, now);) {
            }
            {
                const std::lock_guard<std::mutex> lock(m);
                ids.insert(std::this_thread::get_id());
            }
            std::this_thread::sleep_for(1ms);
            --in_flight;
        }, cap);
        EXPECT_LE(int(ids.size()), cap) << "cap " << cap;
        EXPECT_LE(most.load(), cap) << "cap " << cap;
        if (cap == 1) {
            EXPECT_EQ(*ids.begin(), std::this_thread::get_id()) << "one thread: the caller's";
        }
    }
    // More threads than items: no more threads than items.
    std::mutex m;
    std::set<std::thread::id> ids;
    npf::parallel_for(2, [&](std::size_t) {
        std::this_thread::sleep_for(5ms);
        const std::lock_guard<std::mutex> lock(m);
        ids.insert(std::this_thread::get_id());
    }, 16);
    EXPECT_LE(ids.size(), 2u);
}

TEST(Parallel, ThreadsActuallyRunConcurrently) {
    // Two items that each wait for the other: only completes when both run at once.
    finishes_within(60s, [] {
        std::atomic<int> arrived{0};
        npf::parallel_for(2, [&](std::size_t) {
            ++arrived;
            while (arrived.load() < 2) std::this_thread::yield();
        }, 2);
    });
}

TEST(Parallel, SliceBoundariesDependOnlyOnCountAndSlices) {
    using Slice = std::tuple<std::size_t, std::size_t, std::size_t>;
    auto slices_of = [](std::size_t count, std::size_t slices, int threads) {
        std::mutex m;
        std::set<Slice> seen;
        npf::parallel_slices(count, slices, [&](std::size_t s, std::size_t b, std::size_t e) {
            const std::lock_guard<std::mutex> lock(m);
            EXPECT_TRUE(seen.insert({s, b, e}).second) << "slice " << s << " twice";
        }, threads);
        return seen;
    };
    const std::set<Slice> ten_in_four{{0, 0, 2}, {1, 2, 5}, {2, 5, 7}, {3, 7, 10}};
    const std::set<Slice> three_in_five{{0, 0, 0}, {1, 0, 1}, {2, 1, 1}, {3, 1, 2}, {4, 2, 3}};
    for (int threads : {1, 2, 3, 8, 0}) {
        EXPECT_EQ(slices_of(10, 4, threads), ten_in_four) << threads << " threads";
        EXPECT_EQ(slices_of(3, 5, threads), three_in_five) << threads << " threads";
    }

    // Per-slice partial sums added in slice order: the same bits on any number of threads.
    std::vector<float> values(100003);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = 1.f / float(1 + (i * 7919) % 1013);
    auto sum_on = [&](int threads) {
        std::vector<float> partial(16, 0.f);
        npf::parallel_slices(values.size(), partial.size(), [&](std::size_t s, std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) partial[s] += values[i];
        }, threads);
        float total = 0.f;
        for (float p : partial) total += p;
        return total;
    };
    const float one = sum_on(1);
    for (int threads : {2, 3, 5, 16, 0}) EXPECT_EQ(sum_on(threads), one) << threads << " threads";
}

TEST(Parallel, ProgressFromTheCallingThreadEndingAtOne) {
    const std::thread::id caller = std::this_thread::get_id();
    std::vector<double> reported;
    bool other_thread = false;
    npf::parallel_for(50, [](std::size_t) { std::this_thread::sleep_for(200us); }, 3, [&](double f) {
        other_thread = other_thread || std::this_thread::get_id() != caller;
        reported.push_back(f);
    });
    EXPECT_FALSE(other_thread);
    ASSERT_FALSE(reported.empty());
    EXPECT_EQ(reported.back(), 1.0);
    EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
    for (double f : reported) EXPECT_TRUE(f > 0.0 && f <= 1.0) << f;

    // A failure ends without reporting completion.
    reported.clear();
    EXPECT_THROW(npf::parallel_for(5, [](std::size_t i) {
        if (i == 4) throw std::runtime_error("last");
    }, 1, [&](double f) { reported.push_back(f); }), std::runtime_error);
    EXPECT_EQ(reported, (std::vector<double>{0.2, 0.4, 0.6, 0.8}));
}

TEST(Parallel, ThreadCount) {
    EXPECT_EQ(npf::thread_count(3), 3);
    const int hardware = int(std::max(1u, std::thread::hardware_concurrency()));
    EXPECT_EQ(npf::thread_count(0), hardware);
    EXPECT_EQ(npf::thread_count(-2), hardware);
    npf::ParallelExecutor host;
    host.default_threads = 5;  // a host's limit, on npf's own threads
    const ExecutorGuard guard(host);
    EXPECT_EQ(npf::thread_count(0), 5);
    EXPECT_EQ(npf::thread_count(2), 2);
}

TEST(Parallel, HostExecutorRunsTheTasksWithinTheLimit) {
    std::atomic<int> calls{0};
    std::atomic<std::size_t> most_tasks{0};
    npf::ParallelExecutor host;
    host.run = [&](std::size_t tasks, const std::function<void(std::size_t)>& task) {
        ++calls;
        for (std::size_t seen = most_tasks.load(); tasks > seen && !most_tasks.compare_exchange_weak(seen, tasks);) {
        }
        std::vector<std::thread> threads;
        for (std::size_t t = 0; t < tasks; ++t) threads.emplace_back(task, t);
        for (std::thread& th : threads) th.join();
    };
    host.default_threads = 3;
    {
        const ExecutorGuard guard(host);
        every_index_once(2);
        every_index_once(0);
        EXPECT_GT(calls.load(), 0);
        EXPECT_LE(most_tasks.load(), 3u);
        EXPECT_THROW(npf::parallel_for(10, [](std::size_t i) {
            if (i == 5) throw std::runtime_error("five");
        }, 2), std::runtime_error);
        // One thread: the caller does the work, the executor is not asked.
        const int before = calls.load();
        npf::parallel_for(10, [](std::size_t) {}, 1);
        EXPECT_EQ(calls.load(), before);
    }
    // Uninstalled: npf's own threads again.
    const int after = calls.load();
    every_index_once(2);
    EXPECT_EQ(calls.load(), after);
}

TEST(Parallel, OpenImageIOPoolAsHostExecutor) {
    const ExecutorGuard guard(oiio_executor());
    every_index_once(0);
    every_index_once(3);
    const std::size_t expected = expected_nested_sum();
    finishes_within(60s, [&] { EXPECT_EQ(nested_sum(0), expected); });
    EXPECT_THROW(npf::parallel_for(100, [](std::size_t i) {
        if (i == 42) throw std::runtime_error("42");
    }, 0), std::runtime_error);
    std::vector<float> partial(8, 0.f);
    npf::parallel_slices(1000, partial.size(), [&](std::size_t s, std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) partial[s] += float(i);
    });
    for (std::size_t s = 0; s < partial.size(); ++s) {
        float expected_partial = 0.f;
        for (std::size_t i = 1000 * s / 8; i < 1000 * (s + 1) / 8; ++i) expected_partial += float(i);
        EXPECT_EQ(partial[s], expected_partial) << "slice " << s;
    }
}
