// The primitive every RGL table is made of (docs/rgl-format.md, sec. 3): a stack of W x H
// node tables on the unit square, conditioned on up to two parameters, evaluated bilinearly
// between nodes and multilinearly between parameter slices. Normalised instances also carry
// row and marginal CDFs and provide the forward warp `sample` and its exact inverse `invert`,
// as the reference readers do: the parameter-blended distribution is warped, not the slices.
#pragma once

#include <npf/core/vec.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace npf {

// Where a parameter value sits on an ascending grid: slices `index` and `index + 1` blended
// with weight `t` on the upper one, clamped outside the grid (constant extrapolation). A grid
// of one value is inert (index 0, t 0).
struct GridPosition {
    std::uint32_t index = 0;
    float t = 0.f;
};
GridPosition locate_on_grid(const std::vector<float>& grid, float value);

// The parameter-slice blend of one query: up to four slices with their weights.
struct SliceBlend {
    int count = 1;
    std::uint32_t slice[4] = {0, 0, 0, 0};
    float weight[4] = {1.f, 0.f, 0.f, 0.f};
};

// Blend over two conditioning parameters with grids of sizes n0 x n1 (slice = i0 * n1 + i1).
SliceBlend blend_two_parameters(std::size_t n0, GridPosition p0, std::size_t n1, GridPosition p1);

class PiecewiseLinear2D {
public:
    PiecewiseLinear2D() = default;
    // `values` holds `slices` tables of height x width floats (C order). With `normalize`,
    // each slice becomes a density on [0,1]^2 with its CDFs; a slice must then have positive
    // integral and no negative or non-finite values, else npf::Error naming `source`.
    PiecewiseLinear2D(std::size_t width, std::size_t height, std::size_t slices,
                      std::vector<float> values, bool normalize, const std::string& source);

    std::size_t width() const { return m_width; }
    std::size_t height() const { return m_height; }
    std::size_t slices() const { return m_slices; }
    const std::vector<float>& values() const { return m_data; }

    // Bilinear value at u (clamped to [0,1]^2); a density when normalised.
    float eval(Vec2 u, const SliceBlend& b) const;
    // Forward warp of a uniform point; writes the density at the result. Normalised only.
    Vec2 sample(Vec2 xi, const SliceBlend& b, float* density) const;
    // Inverse of sample: the uniform point that maps to u, and the density at u.
    Vec2 invert(Vec2 u, const SliceBlend& b, float* density) const;

private:
    float blended(const std::vector<float>& table, std::size_t per_slice, const SliceBlend& b,
                  std::size_t k) const;

    std::size_t m_width = 0, m_height = 0, m_slices = 0;
    std::vector<float> m_data;             // [slices][H][W] nodes
    std::vector<float> m_row_cdf;          // [slices][H][W] conditional CDF along each row
    std::vector<float> m_row_integral;     // [slices][H]
    std::vector<float> m_marginal_cdf;     // [slices][H]
};

}  // namespace npf
