// Anderson acceleration of the AWLS sweeps (BlockFit::run), per lane of a block.
#pragma once

#include "block_factors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace npf::fit_detail {

constexpr int kAndersonDepth = 8;  // differences kept

// The last sweeps of a block, and their mix.
template <int L>
class Anderson {
public:
    // Records a sweep: x its start, g its result.
    void push(const BlockFactors<L>& x, const BlockFactors<L>& g);
    // Replaces D, F and G of the lanes it can mix (the result) by the mix; true for those lanes.
    std::array<bool, L> mix(BlockFactors<L>& out) const;

private:
    std::vector<std::vector<float>> m_x, m_g;  // oldest first; D, F and G packed, lanes innermost
    std::size_t m_d = 0, m_f = 0;              // D and F cells
};

// Anderson acceleration (type II; Walker & Ni 2011), per lane. The sweep is a map x -> g(x) of
// the factors (D, F and G; rho_d and rho_s are re-solved for any D, F, G). From the last pairs
// (x_j, g_j) it forms the combination of the results g_j whose residuals g_j - x_j combine to
// the smallest: gamma = argmin |r_m - sum_a gamma_a (r_{a+1} - r_a)|, x = g_m - sum_a gamma_a
// (g_{a+1} - g_a). The norm weighs each table by the mean square of its current values, so
// that D's peak does not outweigh F and G. The mix keeps the gauge (an affine combination of
// normalised factors is normalised) up to the clamp at 0.
template <int L>
void Anderson<L>::push(const BlockFactors<L>& x, const BlockFactors<L>& g) {
    if (int(m_x.size()) == kAndersonDepth + 1) {
        std::rotate(m_x.begin(), m_x.begin() + 1, m_x.end());
        std::rotate(m_g.begin(), m_g.begin() + 1, m_g.end());
        m_x.pop_back();
        m_g.pop_back();
    }
    m_d = x.D.size() / L;
    m_f = x.F.size() / L;
    auto pack = [](const BlockFactors<L>& f, std::vector<float>& v) {
        v.resize(f.D.size() + f.F.size() + f.G.size());
        std::copy(f.D.begin(), f.D.end(), v.begin());
        std::copy(f.F.begin(), f.F.end(), v.begin() + long(f.D.size()));
        std::copy(f.G.begin(), f.G.end(), v.begin() + long(f.D.size() + f.F.size()));
    };
    m_x.emplace_back();
    m_g.emplace_back();
    pack(x, m_x.back());
    pack(g, m_g.back());
}

template <int L>
std::array<bool, L> Anderson<L>::mix(BlockFactors<L>& out) const {
    std::array<bool, L> mixed{};
    const int m = int(m_x.size()) - 1;  // differences
    if (m < 1) return mixed;
    const std::size_t cells = m_x.back().size() / L;
    const std::size_t table_end[3] = {m_d, m_d + m_f, cells};
    const std::vector<float>& now = m_g.back();
    // The weight of each table: one over the mean square of its current values.
    double scale[3][L] = {};
    for (int t = 0, k = 0; t < 3; ++t) {
        const std::size_t begin = std::size_t(k);
        for (; std::size_t(k) < table_end[t]; ++k) {
            for (int l = 0; l < L; ++l) scale[t][l] += double(now[std::size_t(k) * L + std::size_t(l)]) * now[std::size_t(k) * L + std::size_t(l)];
        }
        const double n = double(table_end[t] - begin);
        for (int l = 0; l < L; ++l) scale[t][l] = scale[t][l] > 0.0 ? n / scale[t][l] : 0.0;
    }
    // Normal equations of the least-squares problem for gamma, per lane.
    double M[L][kAndersonDepth][kAndersonDepth] = {}, b[L][kAndersonDepth] = {};
    for (std::size_t k = 0, t = 0; k < cells; ++k) {
        while (k >= table_end[t]) ++t;
        for (int l = 0; l < L; ++l) {
            const std::size_t i = k * L + std::size_t(l);
            double dr[kAndersonDepth];
            double previous = double(m_g[0][i]) - m_x[0][i];
            for (int a = 0; a < m; ++a) {
                const double next = double(m_g[std::size_t(a) + 1][i]) - m_x[std::size_t(a) + 1][i];
                dr[a] = next - previous;
                previous = next;
            }
            const double w = scale[t][l];
            for (int a = 0; a < m; ++a) {
                const double wa = w * dr[a];
                b[l][a] += wa * previous;  // previous is now r_m
                for (int c = 0; c <= a; ++c) M[l][a][c] += wa * dr[c];
            }
        }
    }
    for (int l = 0; l < L; ++l) {
        // Solve with the columns scaled to unit norm and a small ridge, by Gaussian elimination
        // with partial pivoting; a lane whose differences vanish or are dependent is not mixed.
        double A[kAndersonDepth][kAndersonDepth + 1], norm[kAndersonDepth], gamma[kAndersonDepth];
        bool good = true;
        for (int a = 0; a < m; ++a) {
            norm[a] = std::sqrt(M[l][a][a]);
            good = good && norm[a] > 0.0 && std::isfinite(norm[a]);
        }
        if (!good) continue;
        for (int a = 0; a < m; ++a) {
            for (int c = 0; c < m; ++c) A[a][c] = (a >= c ? M[l][a][c] : M[l][c][a]) / (norm[a] * norm[c]);
            A[a][a] += 1e-10;
            A[a][m] = b[l][a] / norm[a];
        }
        for (int a = 0; a < m && good; ++a) {
            int p = a;
            for (int r = a + 1; r < m; ++r) {
                if (std::abs(A[r][a]) > std::abs(A[p][a])) p = r;
            }
            if (!(std::abs(A[p][a]) > 1e-9)) good = false;
            for (int c = 0; c <= m && good; ++c) std::swap(A[a][c], A[p][c]);
            for (int r = a + 1; r < m && good; ++r) {
                const double q = A[r][a] / A[a][a];
                for (int c = a; c <= m; ++c) A[r][c] -= q * A[a][c];
            }
        }
        if (!good) continue;
        for (int a = m - 1; a >= 0; --a) {
            double v = A[a][m];
            for (int c = a + 1; c < m; ++c) v -= A[a][c] * gamma[c];
            gamma[a] = v / A[a][a];
        }
        for (int a = 0; a < m; ++a) {
            gamma[a] /= norm[a];
            good = good && std::isfinite(gamma[a]);
        }
        if (!good) continue;
        auto combine = [&](std::vector<float>& v, std::size_t offset) {
            for (std::size_t k = 0; k < v.size() / L; ++k) {
                const std::size_t i = (offset + k) * L + std::size_t(l);
                double x = m_g[std::size_t(m)][i];
                for (int a = 0; a < m; ++a) x -= gamma[a] * (double(m_g[std::size_t(a) + 1][i]) - m_g[std::size_t(a)][i]);
                v[k * L + std::size_t(l)] = float(std::max(0.0, x));
            }
        };
        combine(out.D, 0);
        combine(out.F, m_d);
        combine(out.G, m_d + m_f);
        mixed[std::size_t(l)] = true;
    }
    return mixed;
}

}  // namespace npf::fit_detail
