// A piecewise-constant density on [0, 1)^2 over a grid of cells, sampled by inversion: a
// marginal distribution over rows, then a conditional distribution over the cells of the chosen
// row (the construction of pbrt's PiecewiseConstant2D and Mitsuba's Hierarchical2D at one
// level). The environment map uses it over its texels.
#pragma once

#include <npf/core/vec.h>

#include <cstddef>
#include <vector>

namespace npf::render {

class PiecewiseConstant2D {
public:
    PiecewiseConstant2D() = default;
    // `weights`: width x height values >= 0, row-major, row 0 at v = 0. The density of a cell
    // is proportional to its weight. When all weights are 0 the density is uniform. Throws
    // npf::Error for a size mismatch, an empty grid, or negative or non-finite weights.
    PiecewiseConstant2D(const std::vector<double>& weights, std::size_t width, std::size_t height);

    std::size_t width() const { return m_width; }
    std::size_t height() const { return m_height; }

    // Draws a point (u, v) in [0, 1)^2 from a uniform point `rnd` in [0, 1)^2 and writes the
    // index (row * width + column) of the cell it lies in. Cells of weight 0 are never drawn.
    Vec2 sample(const Vec2& rnd, std::size_t& cell) const;

    // The density (with respect to du dv) in cell `cell`: weight * width * height / total.
    double density(std::size_t cell) const { return m_density[cell]; }
    // The cell that holds (u, v); coordinates outside [0, 1) are clamped to it.
    std::size_t cell_at(const Vec2& uv) const;

private:
    std::size_t m_width = 0, m_height = 0;
    std::vector<double> m_density;      // per cell
    std::vector<double> m_marginal;     // height + 1 entries, 0 .. 1
    std::vector<double> m_conditional;  // height rows of width + 1 entries, 0 .. 1
};

}  // namespace npf::render
