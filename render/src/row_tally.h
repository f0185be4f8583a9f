// What the rows of a render add up to, from the threads that trace them: hit samples, dropped
// values, and the rows finished, reported as a fraction of `rows` (path_tracer.cpp, lighting.cpp).
#pragma once

#include <npf/render/path_tracer.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>

namespace npf::render {

class RowTally {
public:
    RowTally(std::size_t rows, const RenderProgress& progress) : m_rows(rows), m_progress(progress) {}

    void add_row(std::uint64_t row_hits, std::uint64_t row_dropped) {
        hits += row_hits;
        dropped += row_dropped;
        // Counted under the lock that reports it: counted outside, a row finished later could
        // report before an earlier one, and the fraction would go back (a flaky test showed it).
        const std::lock_guard<std::mutex> lock(m_mutex);
        const std::size_t done = m_rows_done.fetch_add(1) + 1;
        if (m_progress) m_progress(double(done) / double(m_rows));
    }

    std::atomic<std::uint64_t> hits{0}, dropped{0};

private:
    std::size_t m_rows;
    const RenderProgress& m_progress;
    std::atomic<std::size_t> m_rows_done{0};
    std::mutex m_mutex;
};

}  // namespace npf::render
