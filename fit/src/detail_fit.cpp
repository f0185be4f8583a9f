#include <npf/fit/detail_fit.h>

#include "detail_system.h"

#include <npf/fit/rusinkiewicz.h>
#include <npf/fit/spectral_compression.h>
#include <npf/core/error.h>
#include <npf/core/parallel.h>
#include <npf/shading/npf_equation.h>

#include <Imath/half.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

namespace npf {

namespace {

constexpr int kStencil = fit_detail::kDetailStencil;
// Channels beyond this many share one data weight (from their mean), and so one matrix: a
// spectral material's neighbouring wavelengths then also warm-start each other's solve.
constexpr std::size_t kMaxWeightGroups = 16;
// The channels of one weight group are solved in this many chains of neighbouring channels (each
// channel of a chain starting from the previous one's solution, the first from 0), whatever the
// number of threads: the chains run in parallel and the result does not depend on the threads.
// (One chain left a 195-wavelength material's solves, a third of its detail fit, on one core.)
constexpr std::size_t kChainsPerGroup = 4;

const char* const kWhat = "detail layer";

// Slot of corner b relative to corner a in a's 27-point stencil.
int stencil_slot(int dh, int dd, int dp) { return (dh + 1) * 9 + (dd + 1) * 3 + (dp + 1); }

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

Vec3 to_float(const Vec3d& v) { return Vec3(float(v.x), float(v.y), float(v.z)); }

}  // namespace

namespace fit_detail {

HalfDiff DetailSystem::sample_angles(std::size_t a, int b, int c, int e) const {
    HalfDiff hd;
    hd.theta_h = theta_h.angle[a];
    hd.phi_h = phi_h_samples == 1 ? 0.0 : equation::phi_centre(e, phi_h_samples);
    hd.theta_d = theta_d.angle[std::size_t(b)];
    hd.phi_d = phi_d.angle[std::size_t(c)];
    return hd;
}

double DetailSystem::energy_error(const std::vector<double>& model_albedo) const {
    double worst = 0.0;
    for (std::size_t i = 0; i < albedo_source.size(); ++i) {
        if (albedo_source[i] > 1e-4) worst = std::max(worst, std::abs(model_albedo[i] / albedo_source[i] - 1.0));
    }
    return worst;
}

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
        for (int k = 0; k < kStencil; ++k) {
            const std::int32_t j = nb[i * kStencil + std::size_t(k)];
            if (j >= 0) v += s[i * kStencil + std::size_t(k)] * x[std::size_t(j)];
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
    double d = (*stencil)[i * kStencil + std::size_t(stencil_slot(0, 0, 0))];
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

void check_detail_options(const DetailOptions& o) {
    const DetailGrid& g = o.grid;
    if (g.theta_h < 1 || g.theta_d < 1 || g.phi_d < 1 || g.theta_h > 1024 || g.theta_d > 1024 || g.phi_d > 4096 ||
        g.cells() > NpfModel::kMaxDetailCells) {
        throw Error(kWhat, "grid " + std::to_string(g.theta_h) + "x" + std::to_string(g.theta_d) + "x" +
                               std::to_string(g.phi_d) + " is outside 1..1024 x 1..1024 x 1..4096 (" +
                               std::to_string(NpfModel::kMaxDetailCells) + " cells at most)");
    }
    if (o.samples_per_cell < 1 || o.samples_per_cell > 16) throw Error(kWhat, "samples per cell must be 1..16");
    if (o.phi_h_samples < 1 || o.phi_h_samples > 256) throw Error(kWhat, "phi_h samples must be 1..256");
    if (!(o.display_power >= 0.0 && o.display_power <= 4.0)) throw Error(kWhat, "display power must be 0..4");
    if (!(o.display_epsilon > 0.0)) throw Error(kWhat, "display epsilon must be positive");
    if (!(o.energy_weight >= 0.0) || !std::isfinite(o.energy_weight)) throw Error(kWhat, "energy weight must be >= 0");
    if (!(o.smoothness >= 0.0) || !std::isfinite(o.smoothness)) throw Error(kWhat, "smoothness must be >= 0");
    if (!(o.ratio > 0.0 && o.ratio <= 1.0)) throw Error(kWhat, "ratio must lie in (0, 1]");
    if (o.rank < 0) throw Error(kWhat, "rank must be 0 (by ratio) or positive");
    if (o.clamp_passes < 0 || o.clamp_passes > 16) throw Error(kWhat, "clamp passes must be 0..16");
    for (double v : o.energy_views_deg) {
        if (!(v >= 0.0 && v < 90.0)) throw Error(kWhat, "energy views must lie in [0, 90) degrees");
    }
}

// The fit's albedo quadrature at view wi: fn(wo, q) for each wo = reflect(wi, h), h on a
// square-root grid in theta_h (dense at the peak), q = 4 (wi . h) d(omega_h) cos(theta_o), so
// that albedo(wi) = sum q f_r(wi, wo).
template <class Fn>
void for_each_albedo_sample(const Vec3d& wi, Fn&& fn) {
    constexpr int kU = 128, kPhi = 128;
    static const std::array<std::array<double, 2>, kPhi> azimuths = [] {
        std::array<std::array<double, 2>, kPhi> a{};
        for (int b = 0; b < kPhi; ++b) {
            const double phi = kTwoPiD * (b + 0.5) / kPhi;
            a[std::size_t(b)] = {std::cos(phi), std::sin(phi)};
        }
        return a;
    }();
    if (!(wi.z > 1e-6)) return;
    for (int a = 0; a < kU; ++a) {
        const double u = (a + 0.5) / kU, theta_h = equation::theta_h_of_u(u);
        const double dtheta = kPiD * u / kU, sh = std::sin(theta_h), ch = std::cos(theta_h);
        for (int b = 0; b < kPhi; ++b) {
            const Vec3d h{sh * azimuths[std::size_t(b)][0], sh * azimuths[std::size_t(b)][1], ch};
            const double cos_ih = wi.x * h.x + wi.y * h.y + wi.z * h.z;
            if (!(cos_ih > 0.0)) continue;
            const Vec3d wo{2.0 * cos_ih * h.x - wi.x, 2.0 * cos_ih * h.y - wi.y, 2.0 * cos_ih * h.z - wi.z};
            if (!(wo.z > 1e-6)) continue;
            fn(wo, 4.0 * cos_ih * sh * dtheta * (kTwoPiD / kPhi) * wo.z);
        }
    }
}

DetailSystem assemble_detail_system(const Brdf& source, const NpfModel& model, const DetailOptions& o, int threads,
                                    const std::function<void(double)>& progress) {
    check_detail_options(o);
    const ChannelQuery query = source.query(model.channels);
    const std::size_t C = model.channel_count();
    const DetailGrid& g = o.grid;
    const std::size_t cells = g.cells();
    DetailSystem sys;
    sys.grid = g;
    sys.channels = C;
    sys.cells = cells;
    sys.groups = C <= kMaxWeightGroups ? C : 1;
    const std::size_t groups = sys.groups;
    auto group_of = [&](std::size_t c) { return sys.group_of(c); };
    auto report_progress = [&](double f) {
        if (progress) progress(f);
    };

    // ---- The data samples: a regular grid, k per cell and axis --------------------------------
    const int k = o.samples_per_cell;
    const int sh = g.theta_h * k, sd = g.theta_d * k, sp = g.phi_d * k;
    const int se = model.isotropic() ? 1 : o.phi_h_samples;
    DetailAxis& ah = sys.theta_h;
    DetailAxis& ad = sys.theta_d;
    DetailAxis& ap = sys.phi_d;
    sys.phi_h_samples = se;
    for (int a = 0; a < sh; ++a) {
        const double u = (a + 0.5) / sh;
        ah.angle.push_back(equation::theta_h_of_u(u));
        ah.measure.push_back(kPiD * u / sh);  // d(theta_h) = pi u du
        ah.lerp.push_back(detail_position(g, u, 0.0, 0.0).h);
    }
    for (int b = 0; b < sd; ++b) {
        const double td = equation::theta_centre(b, sd);
        ad.angle.push_back(td);
        ad.measure.push_back(kHalfPiD / sd);
        ad.lerp.push_back(detail_position(g, 0.0, td, 0.0).d);
    }
    for (int c = 0; c < sp; ++c) {
        const double pd = equation::phi_centre(c, sp);
        ap.angle.push_back(pd);
        ap.measure.push_back(kTwoPiD / sp);
        ap.lerp.push_back(detail_position(g, 0.0, 0.0, pd).p);
    }
    // Sample (a, b, c, e): theta_h, theta_d, phi_d and phi_h indices, in storage order.
    auto sample_index = [&](std::size_t a, int b, int c, int e) { return sys.sample_index(a, b, c, e); };
    auto sample_angles = [&](std::size_t a, int b, int c, int e) { return sys.sample_angles(a, b, c, e); };
    const std::size_t per_row = std::size_t(sd) * std::size_t(sp) * std::size_t(se);
    const std::size_t samples = std::size_t(sh) * per_row;
    sys.residual.assign(samples * C, 0.f);
    sys.weight.assign(samples * groups, 0.f);
    std::vector<float>& residual = sys.residual;
    std::vector<float>& weight = sys.weight;
    std::vector<double> row_error(std::size_t(sh) * C, 0.0), row_norm(std::size_t(sh) * C, 0.0);
    std::vector<std::size_t> row_valid(std::size_t(sh), 0);
    npf::parallel_slices(std::size_t(sh), std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
        std::vector<float> raw(C);
        std::vector<double> base(C);
        for (std::size_t a = begin; a < end; ++a) {
            for (int b = 0; b < sd; ++b) {
                for (int c = 0; c < sp; ++c) {
                    for (int e = 0; e < se; ++e) {
                        const std::size_t s = sample_index(a, b, c, e);
                        const HalfDiff hd = sample_angles(a, b, c, e);
                        Vec3d wi, wo;
                        directions_from_half_diff(hd, wi, wo);
                        if (!(wi.z > 1e-6) || !(wo.z > 1e-6)) continue;
                        const Vec3 fi = to_float(wi), fo = to_float(wo);
                        source.eval_cos(fi, fo, query, raw.data());
                        model.eval_all(fi, fo, base.data());
                        const double along_h = o.measure == DetailOptions::Measure::SolidAngle ? std::sin(hd.theta_h) : 1.0;
                        const double measure = 4.0 * along_h * std::sin(hd.theta_d) *
                                               std::cos(hd.theta_d) * ah.measure[a] * ad.measure[std::size_t(b)] *
                                               ap.measure[std::size_t(c)] * (kTwoPiD / se) * wi.z * wo.z;
                        double mean = 0.0;
                        bool finite = true;
                        for (std::size_t ch = 0; ch < C; ++ch) {
                            const double f = double(raw[ch]) / fo.z;
                            finite = finite && std::isfinite(f);
                            residual[s * C + ch] = float(f - base[ch]);
                            mean += std::max(f, 0.0);
                        }
                        if (!finite) continue;
                        mean /= double(C);
                        for (std::size_t gr = 0; gr < groups; ++gr) {
                            const double f = groups == 1 ? mean : std::max(double(raw[gr]) / fo.z, 0.0);
                            weight[s * groups + gr] =
                                float(measure * std::pow(f + o.display_epsilon, -o.display_power));
                        }
                        ++row_valid[a];
                        for (std::size_t ch = 0; ch < C; ++ch) {
                            const double w = weight[s * groups + group_of(ch)];
                            const double f = double(raw[ch]) / fo.z;
                            row_error[a * C + ch] += w * double(residual[s * C + ch]) * residual[s * C + ch];
                            row_norm[a * C + ch] += w * f * f;
                        }
                    }
                }
            }
        }
    }, threads);
    report_progress(0.3);

    sys.data_error.assign(C, 0.0);
    sys.data_norm.assign(C, 0.0);
    std::vector<double>& data_error = sys.data_error;
    std::vector<double>& data_norm = sys.data_norm;
    for (std::size_t a = 0; a < std::size_t(sh); ++a) {
        sys.samples_valid += row_valid[a];
        for (std::size_t ch = 0; ch < C; ++ch) {
            data_error[ch] += row_error[a * C + ch];
            data_norm[ch] += row_norm[a * C + ch];
        }
    }

    // ---- The data term's normal equations, one stencil per weight group -----------------------
    // Each cell's rows are summed by the thread that owns its theta_h slice, over the samples in
    // their fixed order: the same sums on any number of threads.
    sys.stencil.assign(groups, std::vector<double>(cells * kStencil, 0.0));
    sys.rhs.assign(C, std::vector<double>(cells, 0.0));
    std::vector<std::vector<double>>& stencil = sys.stencil;
    std::vector<std::vector<double>>& rhs = sys.rhs;
    npf::parallel_slices(std::size_t(g.theta_h), std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t h = begin; h < end; ++h) {
            for (std::size_t a = 0; a < std::size_t(sh); ++a) {
                if (std::size_t(ah.lerp[a].i0) != h && std::size_t(ah.lerp[a].i1) != h) continue;
                for (int b = 0; b < sd; ++b) {
                    for (int c = 0; c < sp; ++c) {
                        const Corners q = corners_of(g, ah.lerp[a], ad.lerp[std::size_t(b)], ap.lerp[std::size_t(c)]);
                        for (int e = 0; e < se; ++e) {
                            const std::size_t s = sample_index(a, b, c, e);
                            for (int j = 0; j < 8; ++j) {
                                if (std::size_t(q.h[j]) != h || q.weight[j] == 0.0) continue;
                                const std::size_t i = q.index[j];
                                for (std::size_t gr = 0; gr < groups; ++gr) {
                                    const double w = weight[s * groups + gr] * q.weight[j];
                                    if (w == 0.0) continue;
                                    double* row = stencil[gr].data() + i * kStencil;
                                    for (int m = 0; m < 8; ++m) {
                                        row[stencil_slot(q.h[m] - q.h[j], q.d[m] - q.d[j],
                                                         periodic_step(q.p[j], q.p[m], g.phi_d))] += w * q.weight[m];
                                    }
                                }
                                for (std::size_t ch = 0; ch < C; ++ch) {
                                    rhs[ch][i] += double(weight[s * groups + group_of(ch)]) * q.weight[j] *
                                                  residual[s * C + ch];
                                }
                            }
                        }
                    }
                }
            }
        }
    }, threads);
    report_progress(0.5);

    // Neighbours of each cell in stencil order (-1 outside the grid).
    sys.neighbour.assign(cells * kStencil, -1);
    std::vector<std::int32_t>& neighbour = sys.neighbour;
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
                            neighbour[i * kStencil + std::size_t(stencil_slot(dh, dd, dp))] =
                                std::int32_t(g.index(hh, ddd, pp));
                        }
                    }
                }
            }
        }
    }
    // Smoothness: lambda (x_i - x_j)^2 over face neighbours, lambda relative to the data term.
    for (std::size_t gr = 0; gr < groups; ++gr) {
        double diagonal_sum = 0.0;
        std::size_t diagonal_count = 0;
        for (std::size_t i = 0; i < cells; ++i) {
            const double d = stencil[gr][i * kStencil + std::size_t(stencil_slot(0, 0, 0))];
            if (d > 0.0) {
                diagonal_sum += d;
                ++diagonal_count;
            }
        }
        const double mean_diagonal = diagonal_count ? diagonal_sum / double(diagonal_count) : 1.0;
        const double lambda = o.smoothness * mean_diagonal;
        const int centre = stencil_slot(0, 0, 0);
        for (std::size_t i = 0; i < cells; ++i) {
            double* row = stencil[gr].data() + i * kStencil;
            row[centre] += 1e-9 * mean_diagonal;  // keeps cells no sample and no neighbour reaches defined
            for (const int slot : {stencil_slot(-1, 0, 0), stencil_slot(1, 0, 0), stencil_slot(0, -1, 0),
                                   stencil_slot(0, 1, 0), stencil_slot(0, 0, -1), stencil_slot(0, 0, 1)}) {
                if (neighbour[i * kStencil + std::size_t(slot)] < 0) continue;
                if (g.phi_d <= 2 && (slot == stencil_slot(0, 0, -1) || slot == stencil_slot(0, 0, 1))) continue;
                row[centre] += lambda;
                row[slot] -= lambda;
            }
        }
    }

    // ---- Energy rows: the directional albedo at each view, by a half-vector quadrature ---------
    // albedo(wi) = integral f(wi, wo) cos(theta_o) d(omega_o), wo = reflect(wi, h),
    // d(omega_o) = 4 (wi . h) d(omega_h), h on a square-root grid in theta_h (dense at the peak).
    std::vector<double> views;
    std::vector<double> view_azimuths;
    if (o.energy_weight > 0.0) {
        const std::vector<double> azimuths = model.isotropic() ? std::vector<double>{0.0}
                                                               : std::vector<double>{0.0, 0.25 * kPiD, 0.5 * kPiD,
                                                                                     0.75 * kPiD};
        for (double v : o.energy_views_deg) {
            for (double phi : azimuths) {
                views.push_back(v * kPiD / 180.0);
                view_azimuths.push_back(phi);
            }
        }
    }
    const std::size_t V = views.size();
    sys.rows.assign(V, std::vector<double>(cells, 0.0));
    sys.albedo_source.assign(V * C, 0.0);
    sys.albedo_base.assign(V * C, 0.0);
    std::vector<std::vector<double>>& rows = sys.rows;
    std::vector<double>& albedo_source = sys.albedo_source;
    std::vector<double>& albedo_base = sys.albedo_base;
    sys.view_wi.clear();
    for (std::size_t v = 0; v < V; ++v) {
        const double st = std::sin(views[v]), ct = std::cos(views[v]);
        sys.view_wi.push_back(Vec3d{st * std::cos(view_azimuths[v]), st * std::sin(view_azimuths[v]), ct});
    }
    {
        npf::parallel_slices(V, std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
            std::vector<float> raw(C);
            std::vector<double> base(C);
            for (std::size_t v = begin; v < end; ++v) {
                const Vec3d wi = sys.view_wi[v];
                for_each_albedo_sample(wi, [&](const Vec3d& wo, double q) {
                        const Vec3 fi = to_float(wi), fo = to_float(wo);
                        source.eval_cos(fi, fo, query, raw.data());
                        model.eval_all(fi, fo, base.data());
                        bool finite = true;
                        for (std::size_t ch = 0; ch < C; ++ch) finite = finite && std::isfinite(raw[ch]);
                        if (!finite) return;
                        for (std::size_t ch = 0; ch < C; ++ch) {
                            albedo_source[v * C + ch] += q * std::max(0.0, double(raw[ch]) / fo.z);
                            albedo_base[v * C + ch] += q * base[ch];
                        }
                        const HalfDiff hd = half_diff_from_directions(wi, wo);
                        const DetailPosition at = detail_position(g, equation::u_of_theta_h(hd.theta_h), hd.theta_d,
                                                                  hd.phi_d);
                        const Trilinear t = trilinear(g, at);
                        for (int j = 0; j < 8; ++j) rows[v][t.index[j]] += q * t.weight[j];
                });
            }
        }, threads);
    }
    report_progress(0.6);

    // ---- Per channel: the energy rows' weights and targets ------------------------------------
    sys.row_weight.assign(C, std::vector<double>(V, 0.0));
    for (std::size_t ch = 0; ch < C; ++ch) {
        if (!(V > 0 && data_error[ch] > 0.0)) continue;
        std::vector<double>& row_weight = sys.row_weight[ch];
        std::vector<double>& b = rhs[ch];
        // A 1 % albedo error at every view costs energy_weight 1e-4 times the base's misfit.
        const double lambda = o.energy_weight * data_error[ch] / double(V);
        double largest = 0.0;
        for (std::size_t v = 0; v < V; ++v) largest = std::max(largest, albedo_source[v * C + ch]);
        for (std::size_t v = 0; v < V; ++v) {
            const double scale = std::max(albedo_source[v * C + ch], 1e-3 * largest);
            if (!(scale > 0.0)) continue;
            row_weight[v] = lambda / (scale * scale);
            const double target = albedo_source[v * C + ch] - albedo_base[v * C + ch];
            for (std::size_t i = 0; i < cells; ++i) b[i] += row_weight[v] * rows[v][i] * target;
        }
    }
    return sys;
}

}  // namespace fit_detail

DetailReport fit_detail_layer(const Brdf& source, NpfModel& model, const DetailOptions& o,
                              const std::function<void(double)>& progress) {
    const auto start = std::chrono::steady_clock::now();
    fit_detail::check_detail_options(o);
    model.detail_grid = DetailGrid{};
    model.detail = SpectralBasis{};
    model.validate(kWhat);
    const std::size_t C = model.channel_count();
    const DetailGrid& g = o.grid;
    const std::size_t cells = g.cells();
    const int threads = npf::thread_count(o.threads);
    auto report_progress = [&](double f) {
        if (progress) progress(f);
    };
    const fit_detail::DetailSystem sys = fit_detail::assemble_detail_system(source, model, o, threads, progress);
    const std::size_t groups = sys.groups;
    auto group_of = [&](std::size_t c) { return sys.group_of(c); };
    const std::size_t V = sys.views();
    const std::vector<double>& data_norm = sys.data_norm;

    DetailReport report;
    report.samples = sys.samples_valid;
    for (std::size_t ch = 0; ch < C; ++ch) {
        report.weighted_error_before += data_norm[ch] > 0.0 ? sys.data_error[ch] / data_norm[ch] / double(C) : 0.0;
    }
    report.energy_error_before = sys.energy_error(sys.albedo_base);

    // ---- Solve per channel ---------------------------------------------------------------------
    std::vector<float> tables(C * cells, 0.f);
    std::vector<int> iterations(C, 0);
    // Each group's channels in order, cut into kChainsPerGroup chains (kChainsPerGroup above).
    std::vector<std::vector<std::size_t>> chains;
    for (std::size_t gr = 0; gr < groups; ++gr) {
        std::vector<std::size_t> members;
        for (std::size_t ch = 0; ch < C; ++ch) {
            if (group_of(ch) == gr) members.push_back(ch);
        }
        const std::size_t count = std::min(kChainsPerGroup, members.size());
        for (std::size_t k = 0; k < count; ++k) {
            chains.emplace_back(members.begin() + long(k * members.size() / count),
                                members.begin() + long((k + 1) * members.size() / count));
        }
    }
    // Each pass solves every channel from the last pass's solution. The first pass holds the
    // energy rows' linear albedo; each later one moves their targets by what the clamp
    // max(0, NPF + r) added at each view in the last pass (measured by the same quadrature), so
    // that the albedo of the layer as stored, clamp included, meets the source's.
    std::vector<std::vector<double>> rhs = sys.rhs;
    std::vector<std::vector<double>> solution(C, std::vector<double>(cells, 0.0));
    std::vector<double> last_gain(V * C, 0.0);
    std::vector<double> albedo_after;  // the stored layer's albedo, clamp included, once measured
    // The model's albedo at each view ([views][channels]) by the energy rows' quadrature, its clamp
    // max(0, NPF + r) included.
    const auto clamped_albedo = [&] {
        std::vector<double> albedo(V * C, 0.0);
        npf::parallel_slices(V, std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
            std::vector<double> with(C);
            for (std::size_t v = begin; v < end; ++v) {
                const Vec3 fi = to_float(sys.view_wi[v]);
                fit_detail::for_each_albedo_sample(sys.view_wi[v], [&](const Vec3d& wo, double q) {
                    NpfModel::Lookup at;
                    if (!model.prepare(fi, to_float(wo), at)) return;
                    model.values(at, with.data());
                    for (std::size_t ch = 0; ch < C; ++ch) albedo[v * C + ch] += q * with[ch];
                });
            }
        }, threads);
        return albedo;
    };
    for (int pass = 0;; ++pass) {
        npf::parallel_for(chains.size(), [&](std::size_t k) {
            std::vector<double> x(cells, 0.0);  // the first pass starts from the chain's last channel
            for (std::size_t ch : chains[k]) {
                if (pass > 0) x = solution[ch];
                const fit_detail::NormalOperator op = fit_detail::NormalOperator::of(sys, ch);
                iterations[ch] = std::max(iterations[ch], fit_detail::solve(op, rhs[ch], x, o.max_iterations, o.tolerance));
                solution[ch] = x;
                for (std::size_t i = 0; i < cells; ++i) tables[ch * cells + i] = float(x[i]);
            }
        }, threads);
        if (pass == 0) report_progress(0.8);

        // ---- Compress across channels, store -----------------------------------------------------
        SpectralBasis basis = compress_tables(tables, C, cells, o.ratio, o.rank, /*per_channel=*/true);
        if (o.half_precision) {
            for (float& v : basis.basis) v = float(Imath::half(v));
        }
        model.detail_grid = g;
        model.detail = std::move(basis);
        if (pass >= o.clamp_passes || V == 0) break;

        // What the clamp adds at each view: the stored layer's albedo, clamp included, minus its
        // linear part (the energy rows' own sums).
        albedo_after = clamped_albedo();
        std::vector<double> gain = albedo_after;
        for (std::size_t v = 0; v < V; ++v) {
            for (std::size_t ch = 0; ch < C; ++ch) {
                double linear = sys.albedo_base[v * C + ch];
                for (std::size_t i = 0; i < cells; ++i) linear += sys.rows[v][i] * model.detail.at(ch, i);
                gain[v * C + ch] -= linear;
            }
        }
        // Settled: the clamp's gain moved no albedo by more than 0.05 % since the last pass.
        double moved = 0.0;
        for (std::size_t v = 0; v < V; ++v) {
            for (std::size_t ch = 0; ch < C; ++ch) {
                const double a = sys.albedo_source[v * C + ch];
                if (a > 0.0) moved = std::max(moved, std::fabs(gain[v * C + ch] - last_gain[v * C + ch]) / a);
            }
        }
        if (moved < 5e-4) break;  // albedo_after is the stored layer's
        albedo_after.clear();
        last_gain = gain;
        rhs = sys.rhs;
        for (std::size_t ch = 0; ch < C; ++ch) {
            if (sys.row_weight[ch].empty()) continue;
            for (std::size_t v = 0; v < V; ++v) {
                const double shift = -sys.row_weight[ch][v] * gain[v * C + ch];
                if (shift == 0.0) continue;
                for (std::size_t i = 0; i < cells; ++i) rhs[ch][i] += shift * sys.rows[v][i];
            }
        }
    }
    for (int it : iterations) report.iterations_max = std::max(report.iterations_max, it);
    model.validate(kWhat);

    // ---- What the stored layer achieves (clamp included) -----------------------------------------
    {
        // Clamp included: the albedo the stored layer gives (npf albedo measures it independently);
        // measured already when the passes settled.
        if (V > 0 && albedo_after.empty()) albedo_after = clamped_albedo();
        report.energy_error_after = sys.energy_error(albedo_after);
        const std::size_t sh = sys.theta_h.angle.size();
        const int sd = int(sys.theta_d.angle.size()), sp = int(sys.phi_d.angle.size()), se = sys.phi_h_samples;
        std::vector<double> error_after(std::size_t(sh) * C, 0.0);
        npf::parallel_slices(std::size_t(sh), std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
            std::vector<double> with(C), without(C);
            for (std::size_t a = begin; a < end; ++a) {
                for (int b = 0; b < sd; ++b) {
                    for (int c = 0; c < sp; ++c) {
                        for (int e = 0; e < se; ++e) {
                            const std::size_t s = sys.sample_index(a, b, c, e);
                            if (!(sys.weight[s * groups] > 0.f)) continue;
                            Vec3d wi, wo;
                            directions_from_half_diff(sys.sample_angles(a, b, c, e), wi, wo);
                            // With and without the layer from one lookup (without it: the model
                            // the layer was fitted to, the same tables, the same bits).
                            NpfModel::Lookup at;
                            if (model.prepare(to_float(wi), to_float(wo), at)) {
                                model.values(at, with.data(), without.data());
                            } else {
                                std::fill(with.begin(), with.end(), 0.0);
                                std::fill(without.begin(), without.end(), 0.0);
                            }
                            for (std::size_t ch = 0; ch < C; ++ch) {
                                const double r = double(sys.residual[s * C + ch]) - (with[ch] - without[ch]);
                                error_after[a * C + ch] += double(sys.weight[s * groups + group_of(ch)]) * r * r;
                            }
                        }
                    }
                }
            }
        }, threads);
        for (std::size_t ch = 0; ch < C; ++ch) {
            double e = 0.0;
            for (std::size_t a = 0; a < std::size_t(sh); ++a) e += error_after[a * C + ch];
            report.weighted_error_after += data_norm[ch] > 0.0 ? e / data_norm[ch] / double(C) : 0.0;
        }
    }
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report_progress(1.0);
    return report;
}

}  // namespace npf
