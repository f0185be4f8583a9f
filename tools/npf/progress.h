// A one-line progress bar on stderr for long work; silent when stderr is not a terminal (logs,
// CI) unless forced, and when disabled.
#pragma once

#include <chrono>
#include <string>

namespace npf::cli {

class ProgressBar {
public:
    ProgressBar(std::string label, bool enabled);
    void update(double fraction);  // 0..1, from one thread
    void finish();
    bool enabled() const { return m_enabled; }

private:
    std::string m_label;
    bool m_enabled;
    int m_last_percent = -1;
    std::chrono::steady_clock::time_point m_start;
};

}  // namespace npf::cli
