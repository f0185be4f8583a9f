// The factors of one block of L channels fitted in lock-step (block_fit.h): every table stored
// cell-major with the L lanes innermost.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

namespace npf::fit_detail {

// One block's factors, lanes innermost.
template <int L>
struct BlockFactors {
    std::vector<float> D, F, G;  // [cells][L]
    std::array<double, L> rho_d{}, rho_s{};
};

// Moves lane l of `y` into `f`.
template <int L>
void copy_lane(const BlockFactors<L>& y, BlockFactors<L>& f, int l) {
    for (std::size_t k = std::size_t(l); k < f.D.size(); k += L) f.D[k] = y.D[k];
    for (std::size_t k = std::size_t(l); k < f.F.size(); k += L) f.F[k] = y.F[k];
    for (std::size_t k = std::size_t(l); k < f.G.size(); k += L) f.G[k] = y.G[k];
    f.rho_d[std::size_t(l)] = y.rho_d[std::size_t(l)];
    f.rho_s[std::size_t(l)] = y.rho_s[std::size_t(l)];
}

}  // namespace npf::fit_detail
