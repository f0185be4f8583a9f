#include <npf/render/piecewise_constant_2d.h>

#include <npf/core/error.h>

#include <algorithm>
#include <cmath>

namespace npf::render {

namespace {

// Index i with cdf[i] <= x < cdf[i + 1], among the n intervals of `cdf` (n + 1 ascending
// entries from 0 to 1). Skips empty intervals; x in [0, 1).
std::size_t find_interval(const double* cdf, std::size_t n, double x) {
    // First entry greater than x, minus one.
    const double* it = std::upper_bound(cdf, cdf + n + 1, x);
    std::size_t i = it == cdf ? 0 : std::size_t(it - cdf) - 1;
    if (i >= n) i = n - 1;
    // x at or beyond the last non-empty interval (rounding): step back onto one with mass.
    while (i > 0 && !(cdf[i + 1] > cdf[i])) --i;
    return i;
}

// Fills cdf[0..n] with the running sums of w[0..n) divided by their total; returns the total.
// A zero total gives the uniform distribution.
double build_cdf(const double* w, std::size_t n, double* cdf) {
    double total = 0.0;
    cdf[0] = 0.0;
    for (std::size_t i = 0; i < n; ++i) cdf[i + 1] = (total += w[i]);
    if (total > 0.0) {
        for (std::size_t i = 1; i <= n; ++i) cdf[i] /= total;
    } else {
        for (std::size_t i = 1; i <= n; ++i) cdf[i] = double(i) / double(n);
    }
    cdf[n] = 1.0;
    return total;
}

}  // namespace

PiecewiseConstant2D::PiecewiseConstant2D(const std::vector<double>& weights, std::size_t width, std::size_t height)
    : m_width(width), m_height(height) {
    if (width == 0 || height == 0) throw Error("piecewise-constant distribution", "empty grid");
    if (weights.size() != width * height)
        throw Error("piecewise-constant distribution", "weight count does not match the grid size");
    for (double w : weights)
        if (!(w >= 0.0) || !std::isfinite(w))
            throw Error("piecewise-constant distribution", "weights must be finite and non-negative");

    m_conditional.resize(height * (width + 1));
    std::vector<double> row_total(height);
    for (std::size_t r = 0; r < height; ++r)
        row_total[r] = build_cdf(&weights[r * width], width, &m_conditional[r * (width + 1)]);
    m_marginal.resize(height + 1);
    const double total = build_cdf(row_total.data(), height, m_marginal.data());

    m_density.resize(width * height);
    const double cells = double(width) * double(height);
    for (std::size_t i = 0; i < width * height; ++i) m_density[i] = total > 0.0 ? weights[i] * cells / total : 1.0;
}

Vec2 PiecewiseConstant2D::sample(const Vec2& rnd, std::size_t& cell) const {
    const double rv = std::clamp(double(rnd.y), 0.0, 1.0), ru = std::clamp(double(rnd.x), 0.0, 1.0);
    const std::size_t row = find_interval(m_marginal.data(), m_height, rv);
    const double* cond = &m_conditional[row * (m_width + 1)];
    const std::size_t col = find_interval(cond, m_width, ru);
    // The position inside the chosen interval, in [0, 1).
    auto offset = [](const double* cdf, std::size_t i, double x) {
        const double width = cdf[i + 1] - cdf[i];
        const double t = width > 0.0 ? (x - cdf[i]) / width : 0.5;
        return std::clamp(t, 0.0, 1.0);
    };
    cell = row * m_width + col;
    double u = (double(col) + offset(cond, col, ru)) / double(m_width);
    double v = (double(row) + offset(m_marginal.data(), row, rv)) / double(m_height);
    // Stay inside the cell after rounding to float.
    const float uf = std::min(float(u), std::nextafter(float(double(col + 1) / double(m_width)), 0.f));
    const float vf = std::min(float(v), std::nextafter(float(double(row + 1) / double(m_height)), 0.f));
    return {std::max(uf, float(double(col) / double(m_width))), std::max(vf, float(double(row) / double(m_height)))};
}

std::size_t PiecewiseConstant2D::cell_at(const Vec2& uv) const {
    auto index = [](float x, std::size_t n) {
        const double t = std::floor(double(x) * double(n));
        if (!(t > 0.0)) return std::size_t(0);  // also NaN
        return std::min(std::size_t(t), n - 1);
    };
    return index(uv.y, m_height) * m_width + index(uv.x, m_width);
}

}  // namespace npf::render
