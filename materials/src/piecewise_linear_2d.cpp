#include <npf/core/clamp.h>
#include <npf/materials/piecewise_linear_2d.h>
#include <npf/core/error.h>

#include <algorithm>
#include <cmath>

namespace npf {

namespace {

float clamp01(float v) { return clamp_range(v, 0.f, 1.f); }  // NaN -> 0
float lerp(float a, float b, float t) { return a + (b - a) * t; }

// tau in [0,1] with a*tau + (b-a)*tau^2/2 = y: where a linear density ramp from a to b over
// a unit interval reaches mass y. The reference readers use (a - sqrt(D)) / (a - b), with a
// special case for a ~ b; that form cancels catastrophically in float just past the special
// case's threshold (errors near 1e-3 in the sampled direction). Multiplying through by the
// conjugate gives the same root without cancellation and without a special case.
float ramp_inverse(float a, float b, float y) {
    const float denominator = a + std::sqrt(clamp_low(a * a + 2.f * y * (b - a), 0.f));
    return denominator > 0.f ? clamp01(2.f * y / denominator) : 0.f;
}

// Largest i in [0, size-2] with pred(i) true, 0 if none; pred must be true then false.
template <typename Pred>
std::size_t find_interval(std::size_t size, const Pred& pred) {
    std::size_t lo = 0, count = size - 2;
    while (count > 0) {  // upper-bound style search over [1, size-2]
        std::size_t half = count / 2, mid = lo + half + 1;
        if (pred(mid)) {
            lo = mid;
            count -= half + 1;
        } else {
            count = half;
        }
    }
    return lo;
}

}  // namespace

GridPosition locate_on_grid(const std::vector<float>& grid, float value) {
    GridPosition p;
    if (grid.size() < 2) return p;
    auto it = std::upper_bound(grid.begin(), grid.end(), value);
    std::size_t i = it == grid.begin() ? 0 : std::size_t(it - grid.begin()) - 1;
    i = std::min(i, grid.size() - 2);
    p.index = std::uint32_t(i);
    p.t = clamp01((value - grid[i]) / (grid[i + 1] - grid[i]));
    return p;
}

SliceBlend blend_two_parameters(std::size_t n0, GridPosition p0, std::size_t n1, GridPosition p1) {
    SliceBlend b;
    b.count = 0;
    const int steps0 = n0 > 1 ? 2 : 1, steps1 = n1 > 1 ? 2 : 1;
    for (int b0 = 0; b0 < steps0; ++b0) {
        for (int b1 = 0; b1 < steps1; ++b1) {
            float w0 = steps0 == 1 ? 1.f : (b0 ? p0.t : 1.f - p0.t);
            float w1 = steps1 == 1 ? 1.f : (b1 ? p1.t : 1.f - p1.t);
            b.slice[b.count] = std::uint32_t((p0.index + b0) * n1 + p1.index + b1);
            b.weight[b.count] = w0 * w1;
            ++b.count;
        }
    }
    return b;
}

PiecewiseLinear2D::PiecewiseLinear2D(std::size_t width, std::size_t height, std::size_t slices,
                                     std::vector<float> values, bool normalize,
                                     const std::string& source)
    : m_width(width), m_height(height), m_slices(slices), m_data(std::move(values)) {
    if (width < 2 || height < 2) {
        throw Error(source, "table is " + std::to_string(height) + " x " + std::to_string(width) +
                                "; every table dimension must be at least 2");
    }
    const std::size_t per_slice = width * height;
    if (m_data.size() != per_slice * slices) throw Error(source, "table size does not match its shape");
    for (std::size_t i = 0; i < m_data.size(); ++i) {
        if (!std::isfinite(m_data[i])) {
            throw Error(source, "non-finite value (" + std::to_string(m_data[i]) + ") at index " +
                                    std::to_string(i));
        }
        if (normalize && m_data[i] < 0.f) {
            throw Error(source, "negative density " + std::to_string(m_data[i]) + " at index " +
                                    std::to_string(i));
        }
    }
    if (!normalize) return;

    // Trapezoid sums are the exact integrals of the bilinear interpolant; accumulate in double.
    m_row_cdf.resize(m_data.size());
    m_row_integral.resize(height * slices);
    m_marginal_cdf.resize(height * slices);
    const double dx = 1.0 / double(width - 1), dy = 1.0 / double(height - 1);
    std::vector<double> cdf(per_slice), rows(height), marginal(height);
    for (std::size_t s = 0; s < slices; ++s) {
        const float* d = m_data.data() + s * per_slice;
        for (std::size_t r = 0; r < height; ++r) {
            cdf[r * width] = 0.0;
            for (std::size_t c = 1; c < width; ++c) {
                cdf[r * width + c] = cdf[r * width + c - 1] +
                                     dx * 0.5 * (double(d[r * width + c - 1]) + double(d[r * width + c]));
            }
            rows[r] = cdf[r * width + width - 1];
        }
        marginal[0] = 0.0;
        for (std::size_t r = 1; r < height; ++r) marginal[r] = marginal[r - 1] + dy * 0.5 * (rows[r - 1] + rows[r]);
        const double total = marginal[height - 1];
        if (!(total > 0.0)) {
            throw Error(source, "slice " + std::to_string(s) + " has zero total density");
        }
        float* dd = m_data.data() + s * per_slice;
        for (std::size_t k = 0; k < per_slice; ++k) {
            dd[k] = float(double(dd[k]) / total);
            m_row_cdf[s * per_slice + k] = float(cdf[k] / total);
        }
        for (std::size_t r = 0; r < height; ++r) {
            m_row_integral[s * height + r] = float(rows[r] / total);
            m_marginal_cdf[s * height + r] = float(marginal[r] / total);
        }
    }
}

inline float PiecewiseLinear2D::blended(const std::vector<float>& table, std::size_t per_slice,
                                 const SliceBlend& b, std::size_t k) const {
    float v = 0.f;
    for (int j = 0; j < b.count; ++j) v += b.weight[j] * table[b.slice[j] * per_slice + k];
    return v;
}

float PiecewiseLinear2D::eval(Vec2 u, const SliceBlend& b) const {
    const std::size_t W = m_width, H = m_height, n = W * H;
    const float gx = clamp01(u.x) * float(W - 1), gy = clamp01(u.y) * float(H - 1);
    const std::size_t c = std::min(std::size_t(gx), W - 2), r = std::min(std::size_t(gy), H - 2);
    const float s = gx - float(c), t = gy - float(r);
    const std::size_t k = r * W + c;
    return lerp(lerp(blended(m_data, n, b, k), blended(m_data, n, b, k + 1), s),
                lerp(blended(m_data, n, b, k + W), blended(m_data, n, b, k + W + 1), s), t);
}

Vec2 PiecewiseLinear2D::sample(Vec2 xi, const SliceBlend& b, float* density) const {
    const std::size_t W = m_width, H = m_height, n = W * H;
    const float dx = 1.f / float(W - 1), dy = 1.f / float(H - 1);
    constexpr float eps = 6e-8f;
    xi.x = clamp_range(xi.x, eps, 1.f - eps);
    xi.y = clamp_range(xi.y, eps, 1.f - eps);

    // Row interval from the (blended) marginal CDF, then the position inside it.
    const std::size_t r = find_interval(H, [&](std::size_t i) { return blended(m_marginal_cdf, H, b, i) < xi.y; });
    const float a = blended(m_row_integral, H, b, r), bb = blended(m_row_integral, H, b, r + 1);
    const float t = ramp_inverse(a, bb, (xi.y - blended(m_marginal_cdf, H, b, r)) / dy);

    // Column interval from the row CDF interpolated at t.
    const float target = xi.x * lerp(a, bb, t);
    auto row_cdf = [&](std::size_t c) {
        return lerp(blended(m_row_cdf, n, b, r * W + c), blended(m_row_cdf, n, b, (r + 1) * W + c), t);
    };
    const std::size_t c = find_interval(W, [&](std::size_t i) { return row_cdf(i) < target; });
    const float p0 = lerp(blended(m_data, n, b, r * W + c), blended(m_data, n, b, (r + 1) * W + c), t);
    const float p1 = lerp(blended(m_data, n, b, r * W + c + 1), blended(m_data, n, b, (r + 1) * W + c + 1), t);
    const float s = ramp_inverse(p0, p1, (target - row_cdf(c)) / dx);
    if (density) *density = lerp(p0, p1, s);
    return {(float(c) + s) * dx, (float(r) + t) * dy};
}

Vec2 PiecewiseLinear2D::invert(Vec2 u, const SliceBlend& b, float* density) const {
    const std::size_t W = m_width, H = m_height, n = W * H;
    const float dx = 1.f / float(W - 1), dy = 1.f / float(H - 1);
    const float gx = clamp01(u.x) * float(W - 1), gy = clamp01(u.y) * float(H - 1);
    const std::size_t c = std::min(std::size_t(gx), W - 2), r = std::min(std::size_t(gy), H - 2);
    const float s = gx - float(c), t = gy - float(r);

    const float p0 = lerp(blended(m_data, n, b, r * W + c), blended(m_data, n, b, (r + 1) * W + c), t);
    const float p1 = lerp(blended(m_data, n, b, r * W + c + 1), blended(m_data, n, b, (r + 1) * W + c + 1), t);
    if (density) *density = lerp(p0, p1, s);
    const float a = blended(m_row_integral, H, b, r), bb = blended(m_row_integral, H, b, r + 1);
    const float row_mass = lerp(a, bb, t);
    const float cdf_at_c =
        lerp(blended(m_row_cdf, n, b, r * W + c), blended(m_row_cdf, n, b, (r + 1) * W + c), t);
    Vec2 xi;
    xi.x = row_mass > 0.f ? (cdf_at_c + dx * (p0 * s + (p1 - p0) * s * s * 0.5f)) / row_mass : 0.f;
    xi.y = blended(m_marginal_cdf, H, b, r) + dy * (a * t + (bb - a) * t * t * 0.5f);
    return xi;
}

}  // namespace npf
