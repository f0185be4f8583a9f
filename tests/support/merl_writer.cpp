#include "merl_writer.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

namespace npf::testing {

namespace {

void put_le(std::vector<std::uint8_t>& out, std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) out.push_back(std::uint8_t(v >> (8 * i)));
}

}  // namespace

void write_merl(const std::string& path, int n_th, int n_td, int n_pd,
                const std::function<void(int ith, int itd, int ipd, double rgb_stored[3])>& fill) {
    const std::size_t bins = std::size_t(std::max(n_th, 0)) * std::size_t(std::max(n_td, 0)) * std::size_t(std::max(n_pd, 0));
    std::vector<double> planes(3 * bins);
    std::size_t index = 0;  // phi_d fastest, then theta_d, then theta_h: the file's order
    for (int ith = 0; ith < n_th; ++ith)
        for (int itd = 0; itd < n_td; ++itd)
            for (int ipd = 0; ipd < n_pd; ++ipd, ++index) {
                double rgb[3] = {0.0, 0.0, 0.0};
                fill(ith, itd, ipd, rgb);
                for (int c = 0; c < 3; ++c) planes[std::size_t(c) * bins + index] = rgb[c];
            }
    std::vector<std::uint8_t> bytes;
    bytes.reserve(12 + 8 * planes.size());
    for (int n : {n_th, n_td, n_pd}) put_le(bytes, std::uint32_t(n), 4);
    for (double v : planes) {
        std::uint64_t raw;
        std::memcpy(&raw, &v, sizeof raw);
        put_le(bytes, raw, 8);
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!out) ADD_FAILURE() << path << ": could not write the MERL file";
}

}  // namespace npf::testing
