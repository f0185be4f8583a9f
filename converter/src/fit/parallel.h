// Runs body(t, begin, end) on `threads` contiguous slices of [0, count), the last slice on the
// calling thread; the first exception thrown by any slice is rethrown after all have joined.
#pragma once

#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace npf::fit_detail {

template <typename Body>
void parallel_slices(std::size_t count, int threads, Body body) {
    std::vector<std::thread> pool;
    std::exception_ptr failure;
    std::mutex m;
    for (int t = 0; t < threads; ++t) {
        const std::size_t b = count * std::size_t(t) / std::size_t(threads);
        const std::size_t e = count * std::size_t(t + 1) / std::size_t(threads);
        auto run = [&, t, b, e] {
            try {
                body(t, b, e);
            } catch (...) {
                std::lock_guard<std::mutex> lock(m);
                if (!failure) failure = std::current_exception();
            }
        };
        if (t + 1 == threads) run();
        else pool.emplace_back(run);
    }
    for (std::thread& th : pool) th.join();
    if (failure) std::rethrow_exception(failure);
}

}  // namespace npf::fit_detail
