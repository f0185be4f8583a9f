// The detail fit's solver (detail_system.h): the normal operator A_c applied without forming it,
// and conjugate gradients on it.
#include "detail_system.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace npf::fit_detail {

NormalOperator NormalOperator::of(const DetailSystem& system, std::size_t channel) {
    NormalOperator op;
    op.stencil = &system.stencil[system.group_of(channel)];
    op.neighbour = &system.neighbour;
    op.rows = &system.rows;
    op.cells = system.cells;
    op.row_weight = system.row_weight[channel];
    return op;
}

void NormalOperator::apply(const std::vector<double>& x, std::vector<double>& y) const {
    const double* s = stencil->data();
    const std::int32_t* nb = neighbour->data();
    for (std::size_t i = 0; i < cells; ++i) {
        double v = 0.0;
        for (int k = 0; k < kDetailStencil; ++k) {
            const std::int32_t j = nb[i * kDetailStencil + std::size_t(k)];
            if (j >= 0) v += s[i * kDetailStencil + std::size_t(k)] * x[std::size_t(j)];
        }
        y[i] = v;
    }
    for (std::size_t v = 0; v < rows->size(); ++v) {
        if (!(row_weight[v] > 0.0)) continue;
        const std::vector<double>& a = (*rows)[v];
        // Four partial sums in a fixed order: one running sum waited on each addition's latency,
        // and these dot products (44 energy rows of a spectral material per apply) were most of
        // the solves' time.
        double part[4] = {0.0, 0.0, 0.0, 0.0};
        std::size_t i = 0;
        for (; i + 4 <= cells; i += 4) {
            for (std::size_t k = 0; k < 4; ++k) part[k] += a[i + k] * x[i + k];
        }
        for (; i < cells; ++i) part[0] += a[i] * x[i];
        const double dot = ((part[0] + part[1]) + (part[2] + part[3])) * row_weight[v];
        for (i = 0; i < cells; ++i) y[i] += a[i] * dot;
    }
}

double NormalOperator::diagonal(std::size_t i) const {
    double d = (*stencil)[i * kDetailStencil + std::size_t(stencil_slot(0, 0, 0))];
    for (std::size_t v = 0; v < rows->size(); ++v) d += row_weight[v] * (*rows)[v][i] * (*rows)[v][i];
    return d;
}

// Jacobi-preconditioned conjugate gradients from the starting point in x; the iterations used.
int solve(const NormalOperator& op, const std::vector<double>& b, std::vector<double>& x, int max_iterations,
          double tolerance) {
    const std::size_t n = op.cells;
    std::vector<double> inv_diag(n), r(n), z(n), p(n), q(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double d = op.diagonal(i);
        inv_diag[i] = d > 0.0 ? 1.0 / d : 0.0;
    }
    op.apply(x, q);
    double b_norm = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        r[i] = b[i] - q[i];
        b_norm += b[i] * b[i];
    }
    b_norm = std::sqrt(b_norm);
    if (!(b_norm > 0.0)) {
        std::fill(x.begin(), x.end(), 0.0);
        return 0;
    }
    double rz = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        z[i] = inv_diag[i] * r[i];
        p[i] = z[i];
        rz += r[i] * z[i];
    }
    int it = 0;
    for (; it < max_iterations; ++it) {
        double r_norm = 0.0;
        for (std::size_t i = 0; i < n; ++i) r_norm += r[i] * r[i];
        if (std::sqrt(r_norm) <= tolerance * b_norm) break;
        op.apply(p, q);
        double pq = 0.0;
        for (std::size_t i = 0; i < n; ++i) pq += p[i] * q[i];
        if (!(pq > 0.0)) break;
        const double alpha = rz / pq;
        double rz_next = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            x[i] += alpha * p[i];
            r[i] -= alpha * q[i];
            z[i] = inv_diag[i] * r[i];
            rz_next += r[i] * z[i];
        }
        const double beta = rz_next / rz;
        rz = rz_next;
        for (std::size_t i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
    }
    return it;
}

}  // namespace npf::fit_detail
