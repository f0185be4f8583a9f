// NpfModel::value_bound: the largest f_r cos(theta_i) cos(theta_o) the tables can give
// (core/include/npf/core/brdf.h, kMaxMaterialValue). Per channel c the projected form is
//   rho_d cos_i cos_o + rho_s D F G_i G_o + r cos_i cos_o  <=  rho_d + rho_s Dmax Fmax Gmax^2 + rmax
// since every interpolated value is a convex combination of cell values (bilinear weights in
// [0, 1]; recombining a spectral basis is linear, so it commutes with interpolation), except G
// beyond its last row centre, which follows the line through its last two rows up to
// 1.5 last - 0.5 prev at the horizon. The projected form needs no 1 / cos bound, so G open at the
// horizon (the paper's preset) is bounded too.
#include <npf/shading/npf_model.h>

#include <npf/core/brdf.h>
#include <npf/shading/npf_equation.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace npf {

namespace {

// Per channel, an upper bound of |recombined value| at any cell, by the triangle inequality:
// sum_k |w_ck| max_cell |basis_k|. Costs rank x cells once, not channels x rank x cells.
std::vector<double> triangle_bound(const SpectralBasis& s, std::size_t channels) {
    std::vector<double> basis_max(std::size_t(s.rank), 0.0);
    for (int k = 0; k < s.rank; ++k) {
        const float* b = s.basis.data() + std::size_t(k) * s.cells;
        double m = 0.0;
        for (std::size_t i = 0; i < s.cells; ++i) m = std::max(m, double(std::fabs(b[i])));
        basis_max[std::size_t(k)] = m;
    }
    std::vector<double> out(channels, 0.0);
    for (std::size_t c = 0; c < channels; ++c) {
        const float* w = s.weights.data() + c * std::size_t(s.rank);
        for (int k = 0; k < s.rank; ++k) out[c] += std::fabs(double(w[k])) * basis_max[std::size_t(k)];
    }
    return out;
}

// Per channel, the largest recombined value at any cell (at least 0: D, G and the sum are clamped
// at 0 when shaded); for G also at the horizon of every column (its extrapolation).
std::vector<double> exact_max(const SpectralBasis& s, std::size_t channels, int g_rows = 0, int g_columns = 0) {
    std::vector<double> out(channels, 0.0);
    std::vector<double> column(s.cells);
    for (std::size_t c = 0; c < channels; ++c) {
        for (std::size_t i = 0; i < s.cells; ++i) column[i] = s.at(c, i);
        double m = *std::max_element(column.begin(), column.end());
        if (g_rows >= 2) {
            for (int j = 0; j < g_columns; ++j) {
                const std::size_t last = std::size_t(g_rows - 1) * std::size_t(g_columns) + std::size_t(j);
                m = std::max(m, equation::g_at_horizon(column[last], column[last - std::size_t(g_columns)]));
            }
        }
        out[c] = std::max(0.0, m);
    }
    return out;
}

std::vector<double> f_max(const NpfModel& m) {
    std::vector<double> out(m.channel_count(), 0.0);
    for (std::size_t c = 0; c < out.size(); ++c) {
        const float* f = m.F.data() + c * std::size_t(m.f_theta);
        out[c] = *std::max_element(f, f + m.f_theta);
    }
    return out;
}

double combine(const NpfModel& m, const std::vector<double>& d, const std::vector<double>& f, const std::vector<double>& g,
               const std::vector<double>& r) {
    double bound = 0.0;
    for (std::size_t c = 0; c < m.channel_count(); ++c) {
        const double v = double(m.rho_d[c]) + double(m.rho_s[c]) * d[c] * f[c] * g[c] * g[c] + (r.empty() ? 0.0 : r[c]);
        bound = std::max(bound, v);
        if (!std::isfinite(v)) return v;
    }
    return bound;
}

}  // namespace

double NpfModel::value_bound() const {
    const std::size_t C = channel_count();
    const std::vector<double> f = f_max(*this);
    // The cheap bound first; G's horizon value is at most 2 max |G| (1.5 last + 0.5 |prev|).
    std::vector<double> g = triangle_bound(G, C);
    for (double& v : g) v *= 2.0;
    const std::vector<double> r = has_detail() ? triangle_bound(detail, C) : std::vector<double>();
    const double cheap = combine(*this, triangle_bound(D, C), f, g, r);
    if (cheap <= kMaxMaterialValue) return cheap;
    // Above the cap: the tables' own maxima, where that costs a few seconds at most (a file at the
    // size caps would need hours; its cheap bound stands, and it is refused).
    const auto work = [C](const SpectralBasis& s) { return double(C) * double(s.rank) * double(s.cells); };
    if (work(D) + work(G) + (has_detail() ? work(detail) : 0.0) > 4e9) return cheap;
    return combine(*this, exact_max(D, C), f, exact_max(G, C, g_theta, g_phi),
                   has_detail() ? exact_max(detail, C) : std::vector<double>());
}

}  // namespace npf
