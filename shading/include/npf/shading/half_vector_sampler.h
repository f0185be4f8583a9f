// The paper's importance sampler (sec. 3.5): the half vector is drawn from the luminance-
// averaged NDF, D_bar(theta_h, phi_h) = sum_c Y_c D_c (Eq. 13 with the project's CIE Y weights),
// tabulated on D's own grid and sampled with an alias table.
//
// The density is piecewise constant in solid angle over D's cells: cell (k, j) spans
//   theta_h in (pi/2) [k/n, (k+1)/n]^2 (the square-root map's cell edges),  phi_h in 2 pi [j, j+1)/m
// and has probability proportional to D_bar(centre) cos(theta_centre) Omega_cell, so that the
// density follows D cos(theta_h), the projected-area NDF, whose integral the fitter fixes at 1.
// Within a cell, h is uniform in solid angle (uniform in cos theta and phi), which makes the pdf
// exact and cheap: pmf(cell) / Omega_cell. Near the pole the cells are tiny, which is where sharp
// peaks need them.
#pragma once

#include <npf/core/sin_cos.h>
#include <npf/core/vec.h>
#include <npf/shading/alias_table.h>
#include <npf/shading/table_interpolation.h>

#include <vector>

namespace npf {

struct NpfModel;

class HalfVectorSampler {
public:
    HalfVectorSampler() = default;
    // `d_bar` holds d_theta x d_phi non-negative values at D's cell centres ([theta][phi]).
    // Throws npf::Error when sizes disagree or no cell has weight.
    HalfVectorSampler(const std::vector<double>& d_bar, int d_theta, int d_phi);

    // D_bar of a model: sum_c y_c max(0, D_c) over its stored channels, with y_c the CIE Y weights
    // of its wavelengths (Rec. 709 luminance for RGB). A small share of the plain channel average
    // (1 %) is mixed in, so that a cell where only channels outside the visible range reflect
    // still gets samples and the estimator stays unbiased for every channel.
    static std::vector<double> luminance_averaged_ndf(const NpfModel& m);

    bool empty() const { return m_cells.empty(); }

    // A half vector in the upper hemisphere from two uniform numbers in [0, 1).
    Vec3 sample(float u1, float u2) const;
    // Solid-angle density of `h` (unit, local frame); 0 below the horizon.
    double pdf(const Vec3& h) const;
    // The same from h's polar angle (radians, [0, pi/2)), its square-root-mapped coordinate
    // u_h = sqrt(theta_h / (pi/2)) and its azimuth ([0, 2 pi)).
    double pdf(double theta_h, double u_h, double phi_h) const;

    // What sample() and pdf() read, for the batched closure's vector code: the cells' alias
    // table, the rows' edges and inverse solid angles, and the grid's size.
    const AliasTable& cells() const { return m_cells; }
    const std::vector<double>& half_sin2() const { return m_half_sin2; }
    const std::vector<double>& inv_solid_angle() const { return m_inv_solid_angle; }
    int theta_cells() const { return m_theta; }
    int phi_cells() const { return m_phi; }
    // Each cell's density (pmf over solid angle, as pdf() computes it) rounded to float, for the
    // float lanes (BatchPrecision::Float): one load per lane instead of the double product.
    const std::vector<float>& cell_density() const { return m_cell_density; }

    // The half vector of a draw in cell (row, column j): s0, s1 the row's edges (half_sin2), t the
    // alias table's remainder, u2 the second number. sample()'s arithmetic, generic over the
    // number type (double, or four doubles in the batched draw) so that both give the same bits.
    template <class T>
    NPF_GENERIC_INLINE static void direction_in_cell(T s0, T s1, T t, T j, T u2, T columns, T& x, T& y, T& z) {
        using table::generic::select;
        using table::generic::sqrt;
        // Uniform in cos theta between the row's edges, uniform in phi across the column.
        const T s = s0 + (s1 - s0) * t;
        const T q = s * (T(1.0) - s);
        const T cos_theta = T(1.0) - T(2.0) * s, sin_theta = T(2.0) * sqrt(select(T(0.0) < q, q, T(0.0)));
        const T phi = T(kTwoPiD) * (j + u2) / columns;
        T sin_phi, cos_phi;
        sin_cos_of(phi, sin_phi, cos_phi);
        x = sin_theta * cos_phi;
        y = sin_theta * sin_phi;
        z = cos_theta;
    }

private:
    int m_theta = 0, m_phi = 0;
    AliasTable m_cells;
    // Per row: sin^2(theta/2) at the cell's lower and upper edge (1 - cos theta = 2 sin^2(theta/2)
    // keeps the pole's tiny cells exact in double).
    std::vector<double> m_half_sin2;  // d_theta + 1 edges
    std::vector<double> m_inv_solid_angle;  // per row: 1 / Omega of one cell
    std::vector<float> m_cell_density;      // [row][column]: cells' pmf times the row's inverse solid angle
};

}  // namespace npf
