#include <npf/fit/spectral_compression.h>

#include <npf/core/error.h>

#include <Eigen/Dense>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <string>

namespace npf {

namespace {

const char* const kSource = "spectral compression";

// Sum of the first `count` squared singular values.
double energy(const std::vector<double>& s, std::size_t count) {
    double e = 0.0;
    for (std::size_t k = 0; k < count && k < s.size(); ++k) e += s[k] * s[k];
    return e;
}

}  // namespace

SpectralBasis compress_tables(const std::vector<float>& tables, std::size_t channels, std::size_t cells, double ratio,
                              int fixed_rank, bool per_channel) {
    Eigen::MatrixXd a(static_cast<Eigen::Index>(cells), static_cast<Eigen::Index>(channels));
    for (std::size_t c = 0; c < channels; ++c) {
        for (std::size_t i = 0; i < cells; ++i) a(Eigen::Index(i), Eigen::Index(c)) = tables[c * cells + i];
    }
    // BDCSVD switches to Jacobi for small matrices; either is accurate to double precision.
    const Eigen::BDCSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
    const Eigen::VectorXd& sigma = svd.singularValues();
    const Eigen::MatrixXd& u = svd.matrixU();
    const Eigen::MatrixXd& v = svd.matrixV();

    SpectralBasis s;
    s.cells = cells;
    s.singular_values.assign(sigma.data(), sigma.data() + sigma.size());
    const int full = int(s.singular_values.size());
    s.rank = fixed_rank > 0 ? std::min(fixed_rank, full) : rank_for_ratio(s.singular_values, ratio);
    if (fixed_rank <= 0 && per_channel && ratio < 1.0) {
        // Channel c keeps sum_{k<r} (sigma_k v_k(c))^2 of its |table_c|^2 = sum over all k.
        for (std::size_t c = 0; c < channels; ++c) {
            double whole = 0.0;
            for (int k = 0; k < full; ++k) whole += std::pow(sigma(k) * v(Eigen::Index(c), k), 2);
            double kept = 0.0;
            int r = 0;
            while (r < full && kept < ratio * whole) {
                kept += std::pow(sigma(r) * v(Eigen::Index(c), r), 2);
                ++r;
            }
            s.rank = std::max(s.rank, r);
        }
    }
    const double total = energy(s.singular_values, s.singular_values.size());
    s.kept_ratio = total > 0.0 ? std::min(1.0, energy(s.singular_values, std::size_t(s.rank)) / total) : 1.0;

    const std::size_t rank = std::size_t(s.rank);
    s.basis.resize(rank * cells);
    s.weights.resize(channels * rank);
    for (std::size_t k = 0; k < rank; ++k) {
        // Sign: the largest-magnitude entry positive (the first of equals).
        Eigen::Index largest = 0;
        for (Eigen::Index i = 1; i < Eigen::Index(cells); ++i) {
            if (std::abs(u(i, Eigen::Index(k))) > std::abs(u(largest, Eigen::Index(k)))) largest = i;
        }
        const double sign = u(largest, Eigen::Index(k)) < 0.0 ? -1.0 : 1.0;
        for (std::size_t i = 0; i < cells; ++i) {
            s.basis[k * cells + i] = float(sign * u(Eigen::Index(i), Eigen::Index(k)));
        }
        for (std::size_t c = 0; c < channels; ++c) {
            s.weights[c * rank + k] = float(sign * sigma(Eigen::Index(k)) * v(Eigen::Index(c), Eigen::Index(k)));
        }
    }
    return s;
}

namespace {

void check_ratio(double ratio, const char* name) {
    if (!(ratio > 0.0 && ratio <= 1.0)) {
        throw Error(kSource, std::string(name) + " ratio " + std::to_string(ratio) + " must lie in (0, 1]");
    }
}

}  // namespace

int rank_for_ratio(const std::vector<double>& singular_values, double ratio) {
    const int full = int(singular_values.size());
    if (full == 0) return 0;
    const double total = energy(singular_values, singular_values.size());
    if (ratio >= 1.0) return full;
    if (!(total > 0.0)) return 1;
    double kept = 0.0;
    for (int r = 1; r <= full; ++r) {
        kept += singular_values[std::size_t(r - 1)] * singular_values[std::size_t(r - 1)];
        if (kept >= ratio * total) return r;
    }
    return full;
}

NpfModel compress_factors(const NpfFactors& f, const CompressionOptions& options) {
    check_ratio(options.d_ratio, "D");
    check_ratio(options.g_ratio, "G");
    if (options.d_rank < 0 || options.g_rank < 0) throw Error(kSource, "ranks must be 0 (by ratio) or positive");

    const std::size_t C = f.channel_count();
    if (C == 0) throw Error(kSource, "the factors hold no channels");
    if (f.channels.size() != C || f.rho_s.size() != C || f.D.size() != C * f.d_size() ||
        f.F.size() != C * std::size_t(f.grid.theta_d) || f.G.size() != C * f.g_size() || f.d_size() == 0 ||
        f.g_size() == 0 || f.grid.theta_d < 1) {
        throw Error(kSource, "the factor tables' sizes disagree with their grids and channel count");
    }

    NpfModel m;
    m.channels = f.channels;
    m.d_theta = f.grid.theta_h;
    m.d_phi = f.grid.phi_h;
    m.f_theta = f.grid.theta_d;
    m.g_theta = f.g_theta;
    m.g_phi = f.g_phi;
    m.rho_d = f.rho_d;
    m.rho_s = f.rho_s;
    m.F = f.F;
    m.D = compress_tables(f.D, C, f.d_size(), options.d_ratio, options.d_rank, options.per_channel);
    m.G = compress_tables(f.G, C, f.g_size(), options.g_ratio, options.g_rank, options.per_channel);
    return m;
}

}  // namespace npf
