#include <npf/render/environment_spectra.h>

#include <npf/core/parallel.h>

#include <algorithm>

namespace npf::render {

EnvironmentSpectra::EnvironmentSpectra(const EnvironmentMap& map, unsigned threads_wanted) {
    color::prepare_rgb_sigmoid_table();
    const std::size_t n = map.width() * map.height();
    m_spectra.resize(n);
    const std::vector<float>& px = map.pixels();
    // Texels are independent, so the result does not depend on the split or the thread count.
    // Small maps are not worth a thread; larger ones go in at most 64 runs of texels.
    const int threads = npf::thread_count(int(threads_wanted));
    const std::size_t slices = n < 65536 ? 1 : std::min<std::size_t>(std::size_t(threads), 64);
    npf::parallel_slices(n, slices, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            m_spectra[i] = color::RgbUnboundedSpectrum({double(px[i * 3]), double(px[i * 3 + 1]), double(px[i * 3 + 2])});
    }, threads);
}

}  // namespace npf::render
