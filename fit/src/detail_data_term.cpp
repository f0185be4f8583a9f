// The detail fit's data term as normal equations (detail_steps.h): each sample's trilinear
// weights on its 8 corner cells make one row of the least-squares problem; A^T W A is a 27-point
// stencil per cell. Then the smoothness term, folded into the same stencils.
#include "detail_steps.h"

#include <npf/core/parallel.h>

#include <cstdint>

namespace npf::fit_detail {

namespace {

int periodic_step(int from, int to, int n) {
    const int d = ((to - from) % n + n) % n;
    return d == 0 ? 0 : (d == 1 ? 1 : -1);
}

struct Corners {
    int h[8], d[8], p[8];
    std::uint32_t index[8];
    double weight[8];
};

Corners corners_of(const DetailGrid& g, const table::Lerp& h, const table::Lerp& d, const table::Lerp& p) {
    Corners c;
    int k = 0;
    for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) {
            for (int e = 0; e < 2; ++e, ++k) {
                c.h[k] = a ? h.i1 : h.i0;
                c.d[k] = b ? d.i1 : d.i0;
                c.p[k] = e ? p.i1 : p.i0;
                c.index[k] = std::uint32_t(g.index(c.h[k], c.d[k], c.p[k]));
                c.weight[k] = (a ? h.t : 1.0 - h.t) * (b ? d.t : 1.0 - d.t) * (e ? p.t : 1.0 - p.t);
            }
        }
    }
    return c;
}

// Adds sample s's rows to the stencils and right-hand sides of the cells in theta_h row h among
// its corners q.
void add_sample(DetailSystem& sys, const Corners& q, std::size_t s, std::size_t h) {
    const std::size_t C = sys.channels, groups = sys.groups;
    for (int j = 0; j < 8; ++j) {
        if (std::size_t(q.h[j]) != h || q.weight[j] == 0.0) continue;
        const std::size_t i = q.index[j];
        for (std::size_t gr = 0; gr < groups; ++gr) {
            const double w = sys.weight[s * groups + gr] * q.weight[j];
            if (w == 0.0) continue;
            double* row = sys.stencil[gr].data() + i * kDetailStencil;
            for (int m = 0; m < 8; ++m) {
                row[stencil_slot(q.h[m] - q.h[j], q.d[m] - q.d[j], periodic_step(q.p[j], q.p[m], sys.grid.phi_d))] +=
                    w * q.weight[m];
            }
        }
        for (std::size_t ch = 0; ch < C; ++ch) {
            sys.rhs[ch][i] += double(sys.weight[s * groups + sys.group_of(ch)]) * q.weight[j] * sys.residual[s * C + ch];
        }
    }
}

// Neighbours of each cell in stencil order (-1 outside the grid).
std::vector<std::int32_t> neighbours(const DetailGrid& g) {
    std::vector<std::int32_t> neighbour(g.cells() * kDetailStencil, -1);
    for (int h = 0; h < g.theta_h; ++h) {
        for (int d = 0; d < g.theta_d; ++d) {
            for (int p = 0; p < g.phi_d; ++p) {
                const std::size_t i = g.index(h, d, p);
                for (int dh = -1; dh <= 1; ++dh) {
                    for (int dd = -1; dd <= 1; ++dd) {
                        for (int dp = -1; dp <= 1; ++dp) {
                            const int hh = h + dh, ddd = d + dd;
                            if (hh < 0 || hh >= g.theta_h || ddd < 0 || ddd >= g.theta_d) continue;
                            // A periodic axis of 1 or 2 cells reaches the same neighbour both ways:
                            // the assembly uses the slot periodic_step names, the other stays 0.
                            const int pp = ((p + dp) % g.phi_d + g.phi_d) % g.phi_d;
                            if (dp != 0 && periodic_step(p, pp, g.phi_d) != dp) continue;
                            neighbour[i * kDetailStencil + std::size_t(stencil_slot(dh, dd, dp))] =
                                std::int32_t(g.index(hh, ddd, pp));
                        }
                    }
                }
            }
        }
    }
    return neighbour;
}

}  // namespace

void add_data_term(int threads, DetailSystem& sys) {
    const DetailGrid& g = sys.grid;
    sys.stencil.assign(sys.groups, std::vector<double>(sys.cells * kDetailStencil, 0.0));
    sys.rhs.assign(sys.channels, std::vector<double>(sys.cells, 0.0));
    const std::size_t sh = sys.theta_h.angle.size();
    const int sd = int(sys.theta_d.angle.size()), sp = int(sys.phi_d.angle.size()), se = sys.phi_h_samples;
    // Each cell's rows are summed by the thread that owns its theta_h slice, over the samples in
    // their fixed order: the same sums on any number of threads.
    npf::parallel_slices(std::size_t(g.theta_h), std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t h = begin; h < end; ++h) {
            for (std::size_t a = 0; a < sh; ++a) {
                const table::Lerp& lh = sys.theta_h.lerp[a];
                if (std::size_t(lh.i0) != h && std::size_t(lh.i1) != h) continue;
                for (int b = 0; b < sd; ++b) {
                    for (int c = 0; c < sp; ++c) {
                        const Corners q = corners_of(g, lh, sys.theta_d.lerp[std::size_t(b)], sys.phi_d.lerp[std::size_t(c)]);
                        for (int e = 0; e < se; ++e) add_sample(sys, q, sys.sample_index(a, b, c, e), h);
                    }
                }
            }
        }
    }, threads);
}

// Smoothness: lambda (x_i - x_j)^2 over face neighbours, lambda relative to the data term.
void add_smoothness(const DetailOptions& o, DetailSystem& sys) {
    sys.neighbour = neighbours(sys.grid);
    const std::size_t cells = sys.cells;
    const int centre = stencil_slot(0, 0, 0);
    for (std::vector<double>& stencil : sys.stencil) {
        double diagonal_sum = 0.0;
        std::size_t diagonal_count = 0;
        for (std::size_t i = 0; i < cells; ++i) {
            const double d = stencil[i * kDetailStencil + std::size_t(centre)];
            if (d > 0.0) {
                diagonal_sum += d;
                ++diagonal_count;
            }
        }
        const double mean_diagonal = diagonal_count ? diagonal_sum / double(diagonal_count) : 1.0;
        const double lambda = o.smoothness * mean_diagonal;
        for (std::size_t i = 0; i < cells; ++i) {
            double* row = stencil.data() + i * kDetailStencil;
            row[centre] += 1e-9 * mean_diagonal;  // keeps cells no sample and no neighbour reaches defined
            for (const int slot : {stencil_slot(-1, 0, 0), stencil_slot(1, 0, 0), stencil_slot(0, -1, 0),
                                   stencil_slot(0, 1, 0), stencil_slot(0, 0, -1), stencil_slot(0, 0, 1)}) {
                if (sys.neighbour[i * kDetailStencil + std::size_t(slot)] < 0) continue;
                if (sys.grid.phi_d <= 2 && (slot == stencil_slot(0, 0, -1) || slot == stencil_slot(0, 0, 1))) continue;
                row[centre] += lambda;
                row[slot] -= lambda;
            }
        }
    }
}

}  // namespace npf::fit_detail
