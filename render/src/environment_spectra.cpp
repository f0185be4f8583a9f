#include <npf/render/environment_spectra.h>

#include <algorithm>
#include <thread>

namespace npf::render {

EnvironmentSpectra::EnvironmentSpectra(const EnvironmentMap& map, unsigned threads_wanted) {
    color::prepare_rgb_sigmoid_table();
    const std::size_t n = map.width() * map.height();
    m_spectra.resize(n);
    const std::vector<float>& px = map.pixels();
    // Texels are independent, so the result does not depend on the thread count.
    auto work = [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            m_spectra[i] = color::RgbUnboundedSpectrum({double(px[i * 3]), double(px[i * 3 + 1]), double(px[i * 3 + 2])});
    };
    const unsigned hw = threads_wanted > 0 ? threads_wanted : std::max(1u, std::thread::hardware_concurrency());
    const std::size_t threads = n < 65536 ? 1 : std::min<std::size_t>(hw, 64);
    std::vector<std::thread> pool;
    const std::size_t chunk = (n + threads - 1) / threads;
    for (std::size_t t = 1; t < threads; ++t)
        pool.emplace_back(work, std::min(n, t * chunk), std::min(n, (t + 1) * chunk));
    work(0, std::min(n, chunk));
    for (std::thread& t : pool) t.join();
}

}  // namespace npf::render
