#include <npf/shading/half_vector_sampler.h>

#include "luminance.h"

#include <npf/core/error.h>
#include <npf/shading/npf_equation.h>
#include <npf/shading/npf_model.h>
#include <npf/shading/table_interpolation.h>

#include <algorithm>
#include <cmath>

namespace npf {

HalfVectorSampler::HalfVectorSampler(const std::vector<double>& d_bar, int d_theta, int d_phi)
    : m_theta(d_theta), m_phi(d_phi) {
    if (d_theta < 1 || d_phi < 1 || d_bar.size() != std::size_t(d_theta) * std::size_t(d_phi)) {
        throw Error("half-vector sampler", "the NDF table's size disagrees with its grid");
    }
    m_half_sin2.resize(std::size_t(d_theta) + 1);
    for (int k = 0; k <= d_theta; ++k) {
        const double theta = equation::theta_h_of_u(double(k) / d_theta), s = std::sin(0.5 * theta);
        m_half_sin2[std::size_t(k)] = s * s;
    }
    const double d_phi_width = kTwoPiD / d_phi;
    m_inv_solid_angle.resize(std::size_t(d_theta));
    std::vector<double> weight(d_bar.size());
    for (int k = 0; k < d_theta; ++k) {
        const double omega = 2.0 * (m_half_sin2[std::size_t(k) + 1] - m_half_sin2[std::size_t(k)]) * d_phi_width;
        m_inv_solid_angle[std::size_t(k)] = 1.0 / omega;
        const double cos_centre = std::cos(equation::theta_h_centre(k, d_theta));
        for (int j = 0; j < d_phi; ++j) {
            const std::size_t cell = std::size_t(k) * std::size_t(d_phi) + std::size_t(j);
            const double v = d_bar[cell];
            if (!std::isfinite(v) || v < 0.0) throw Error("half-vector sampler", "NDF values must be finite and >= 0");
            weight[cell] = v * cos_centre * omega;
        }
    }
    m_cells = AliasTable(weight);  // throws when every weight is 0
    m_cell_density.resize(weight.size());
    for (std::size_t cell = 0; cell < weight.size(); ++cell)
        m_cell_density[cell] = float(double(m_cells.pmf(cell)) * m_inv_solid_angle[cell / std::size_t(d_phi)]);
}

std::vector<double> HalfVectorSampler::luminance_averaged_ndf(const NpfModel& m) {
    const std::size_t C = m.channel_count();
    std::vector<double> y = luminance_weights_of(m.channels);
    for (double& v : y) v = 0.99 * v + 0.01 / double(C);
    std::vector<double> d_bar(m.D.cells, 0.0);
    // A cell's basis values gathered once (they lie a table apart), then every channel's D from
    // them: the sums of SpectralBasis::at in its order, without C strided passes per cell.
    const std::size_t rank = std::size_t(m.D.rank);
    std::vector<float> b(rank);
    for (std::size_t cell = 0; cell < m.D.cells; ++cell) {
        for (std::size_t k = 0; k < rank; ++k) b[k] = m.D.basis[k * m.D.cells + cell];
        double v = 0.0;
        for (std::size_t c = 0; c < C; ++c) {
            const float* w = m.D.weights.data() + c * rank;
            double d = 0.0;
            for (std::size_t k = 0; k < rank; ++k) d += double(w[k]) * b[k];
            v += y[c] * std::max(0.0, d);
        }
        d_bar[cell] = v;
    }
    return d_bar;
}

Vec3 HalfVectorSampler::sample(float u1, float u2) const {
    const AliasTable::Draw cell = m_cells.sample(u1);
    const std::size_t k = cell.index / std::uint32_t(m_phi), j = cell.index % std::uint32_t(m_phi);
    double x, y, z;
    direction_in_cell(m_half_sin2[k], m_half_sin2[k + 1], double(cell.remainder), double(j), double(u2), double(m_phi), x,
                      y, z);
    return Vec3(float(x), float(y), float(z));
}

double HalfVectorSampler::pdf(const Vec3& h) const {
    if (!(h.z > 0.f)) return 0.0;
    const double theta = table::polar(h.x, h.y, h.z);
    return pdf(theta, equation::u_of_theta_h(theta), table::azimuth(h.x, h.y));
}

double HalfVectorSampler::pdf(double theta, double u, double phi) const {
    if (m_cells.empty() || !(theta < kHalfPiD) || !(phi >= 0.0)) return 0.0;
    const int k = std::min(int(u * m_theta), m_theta - 1);
    const int j = std::min(int(phi / kTwoPiD * m_phi), m_phi - 1);
    return double(m_cells.pmf(std::size_t(k) * std::size_t(m_phi) + std::size_t(j))) * m_inv_solid_angle[std::size_t(k)];
}

}  // namespace npf
