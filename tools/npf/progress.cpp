#include "progress.h"

#include <cstdio>
#include <unistd.h>

namespace npf::cli {

ProgressBar::ProgressBar(std::string label, bool enabled)
    : m_label(std::move(label)), m_enabled(enabled && ::isatty(STDERR_FILENO)), m_start(std::chrono::steady_clock::now()) {}

void ProgressBar::update(double fraction) {
    if (!m_enabled) return;
    const int percent = int(fraction * 100.0);
    if (percent == m_last_percent) return;
    m_last_percent = percent;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    const int width = 30, filled = int(fraction * width);
    std::string bar(std::size_t(filled), '#');
    bar.resize(std::size_t(width), '.');
    std::fprintf(stderr, "\r%s [%s] %3d%% %5.1f s", m_label.c_str(), bar.c_str(), percent, elapsed);
    std::fflush(stderr);
}

void ProgressBar::finish() {
    if (m_enabled && m_last_percent >= 0) std::fprintf(stderr, "\n");
}

}  // namespace npf::cli
