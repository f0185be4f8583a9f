#include <npf/materials/rgl_writer.h>

#include "rgl_u_space.h"

#include <npf/color/spectrum.h>
#include <npf/materials/piecewise_linear_2d.h>
#include <npf/materials/tensor_file.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/core/parallel.h>
#include <npf/core/rec709_luminance.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <iterator>
#include <cmath>
#include <random>

namespace npf {

namespace {

constexpr double kPiD2 = kPiD * kPiD;

// Directions at exactly the horizon evaluate to 0 in every source; measurements (and the
// reference acquisition code) lift them slightly above it.
constexpr float kHorizonLift = 1e-4f;

Vec3 node_direction(float u_theta, float u_phi, float phi_offset) {
    return spherical_direction(u_to_theta(u_theta), u_to_phi(u_phi) + phi_offset);
}

Vec3 lifted(const Vec3& w) {
    if (w.z >= kHorizonLift) return w;
    const float r = std::sqrt(std::max(0.f, 1.f - kHorizonLift * kHorizonLift));
    const float h = std::sqrt(w.x * w.x + w.y * w.y);
    return h > 0.f ? Vec3(w.x / h * r, w.y / h * r, kHorizonLift) : Vec3(0.f, 0.f, 1.f);
}

// Luminance of one evaluation's channel values: Rec. 709 weights for RGB, CIE Y weights
// (reflectance convention of npf/color/spectrum.h) for wavelengths.
struct LuminanceWeights {
    std::vector<double> w;
    explicit LuminanceWeights(const Channels& c) {
        if (c.is_rgb()) {
            w.assign(std::begin(kRec709Luminance), std::end(kRec709Luminance));
        } else {
            w = color::luminance_weights(c.wavelengths());
        }
    }
    double operator()(const float* v) const {
        double y = 0.0;
        for (std::size_t k = 0; k < w.size(); ++k) y += w[k] * double(v[k]);
        return y;
    }
};

// A table of rows x cols nodes over u-space (row: u_phi, column: u_theta).
struct NodeTable {
    int rows = 0, cols = 0;
    std::vector<float> values;
    float u_theta(int c) const { return float(c) / float(cols - 1); }
    float u_phi(int r) const { return float(r) / float(rows - 1); }
};

// D recovered from retro-reflection (sec. 9 W1 b): the dominant eigenvector of
// K(w, m) = g(w) max(0, w.m), g(w) = f_r(w, w) cos(theta) (luminance), on a coarse grid,
// then extended to the table nodes by one application of the kernel.
NodeTable ndf_by_power_iteration(const Brdf& source, const ChannelQuery& query, const LuminanceWeights& lum,
                                 NodeTable table, int iterations) {
    const int grid_rows = table.rows > 2 ? 32 : 16, grid_cols = 48;
    struct Node {
        Vec3 m;
        double weight;
    };
    std::vector<Node> nodes;
    std::vector<float> values(query.size());
    auto retro = [&](const Vec3& w) {
        const Vec3 d = lifted(w);
        source.eval_cos(d, d, query, values.data());
        return std::max(0.0, lum(values.data()));
    };
    std::vector<double> g;
    const double du = 1.0 / (grid_cols - 1), dv = 1.0 / (grid_rows - 1);
    for (int r = 0; r < grid_rows; ++r) {
        for (int c = 0; c < grid_cols; ++c) {
            const float ux = float(c * du), uy = float(r * dv);
            const Vec3 m = node_direction(ux, uy, 0.f);
            const double end_x = (c == 0 || c == grid_cols - 1) ? 0.5 : 1.0;
            const double end_y = (r == 0 || r == grid_rows - 1) ? 0.5 : 1.0;
            const double w = 2.0 * kPiD2 * ux * std::sin(u_to_theta(ux)) * du * dv * end_x * end_y;
            nodes.push_back({m, w});
            g.push_back(retro(m));
        }
    }
    const std::size_t n = nodes.size();
    std::vector<double> d(n, 1.0), next(n);
    for (int it = 0; it < iterations; ++it) {
        double norm = 0.0;
        for (std::size_t j = 0; j < n; ++j) {
            double sum = 0.0;
            for (std::size_t k = 0; k < n; ++k) sum += std::max(0.f, dot(nodes[j].m, nodes[k].m)) * d[k] * nodes[k].weight;
            next[j] = g[j] * sum;
            norm = std::max(norm, next[j]);
        }
        if (!(norm > 0.0)) throw Error(source.info().path, "retro-reflection is zero everywhere: no NDF to recover");
        for (std::size_t j = 0; j < n; ++j) d[j] = next[j] / norm;
    }
    for (int r = 0; r < table.rows; ++r) {
        for (int c = 0; c < table.cols; ++c) {
            const Vec3 m = node_direction(table.u_theta(c), table.u_phi(r), 0.f);
            double sum = 0.0;
            for (std::size_t k = 0; k < n; ++k) sum += std::max(0.f, dot(m, nodes[k].m)) * d[k] * nodes[k].weight;
            table.values[std::size_t(r) * table.cols + c] = float(retro(m) * sum);
        }
    }
    return table;
}

// sigma(w) = integral max(0, w.m) D(m) dm of the bilinear interpolant of the NDF table (what
// readers see), by a midpoint rule on 4 x 4 points per table cell in u-space, where
// d(omega) = 2 pi^2 u sin(theta) du dv.
struct ProjectedAreaIntegrator {
    std::vector<Vec3> m;
    std::vector<double> a;  // D(m) times the quadrature weight
    ProjectedAreaIntegrator(const PiecewiseLinear2D& ndf, int rows, int cols, bool isotropic) {
        const int sub = 4;
        const int phi_cells = isotropic ? 64 : rows - 1;
        const double du = 1.0 / ((cols - 1) * sub), dv = 1.0 / (phi_cells * sub);
        for (int i = 0; i < (cols - 1) * sub; ++i) {
            const double ux = (i + 0.5) * du;
            const double jac = 2.0 * kPiD2 * ux * std::sin(double(u_to_theta(float(ux)))) * du * dv;
            for (int j = 0; j < phi_cells * sub; ++j) {
                const double uy = (j + 0.5) * dv;
                const double dval = ndf.eval({float(ux), float(uy)}, SliceBlend());
                if (dval <= 0.0) continue;
                m.push_back(node_direction(float(ux), float(uy), 0.f));
                a.push_back(dval * jac);
            }
        }
    }
    double operator()(const Vec3& w) const {
        double s = 0.0;
        for (std::size_t k = 0; k < m.size(); ++k) s += std::max(0.f, dot(w, m[k])) * a[k];
        return s;
    }
};

std::vector<std::uint64_t> shape(std::initializer_list<std::size_t> dims) {
    std::vector<std::uint64_t> s;
    for (std::size_t d : dims) s.push_back(std::uint64_t(d));
    return s;
}

void check_options(const RglWriterOptions& o, const std::string& path) {
    auto at_least = [&](int v, int lo, const char* name) {
        if (v < lo) throw Error(path, std::string("writer option ") + name + " = " + std::to_string(v) +
                                          " must be at least " + std::to_string(lo));
    };
    at_least(o.theta_count, 2, "theta_count");
    at_least(o.ndf_size, 2, "ndf_size");
    at_least(o.ndf_rows, 2, "ndf_rows");
    at_least(o.vndf_size, 2, "vndf_size");
    at_least(o.data_size, 2, "data_size");
    at_least(o.power_iterations, 1, "power_iterations");
    if (o.anisotropy != AnisotropyMode::Isotropic) at_least(o.phi_count, 3, "phi_count");
    // Every field within what the reader takes (TensorFile::kMaxFieldBytes): a recipe's grid of
    // 4096 on every axis asked for 10^17 bytes; a file its own reader refuses is not written.
    const std::uint64_t phi = o.anisotropy == AnisotropyMode::Isotropic ? 1 : std::uint64_t(std::max(o.phi_count, 1));
    const std::uint64_t slices = phi * std::uint64_t(std::max(o.theta_count, 1)), C = o.channels.size();
    const std::uint64_t vndf = std::uint64_t(std::max(o.vndf_size, 1)), data = std::uint64_t(std::max(o.data_size, 1));
    for (const auto& [name, bytes] : {std::pair<const char*, std::uint64_t>{"vndf", slices * vndf * vndf * 4},
                                      {"data", slices * C * data * data * 4},
                                      {"ndf", std::uint64_t(std::max(o.ndf_rows, 1)) * std::uint64_t(std::max(o.ndf_size, 1)) * 4}}) {
        if (bytes > TensorFile::kMaxFieldBytes)
            throw Error(path, std::string("the grid asks for a field '") + name + "' of " + std::to_string(bytes >> 20) +
                                  " MiB; an RGL field may hold at most " + std::to_string(TensorFile::kMaxFieldBytes >> 20) +
                                  " MiB (the reader's cap): choose smaller phi, theta, vndf or data sizes");
    }
    if (!o.channels.is_rgb() && o.channels.wavelengths().empty()) throw Error(path, "no wavelengths to write");
    if (!o.channels.is_rgb()) {
        const std::vector<float>& w = o.channels.wavelengths();
        for (std::size_t i = 1; i < w.size(); ++i) {
            if (!(w[i] > w[i - 1])) throw Error(path, "wavelengths to write must be strictly ascending");
        }
    }
}

// The options' grids, and what the stages share: the source, its query, the slices' directions.
struct Acquisition {
    const Brdf& source;
    const RglWriterOptions& options;
    const std::string& path;
    ChannelQuery query;
    LuminanceWeights luminance;
    int threads;
    bool iso;
    std::vector<float> phi_i, theta_i;
    std::size_t nP = 0, nT = 0, slices = 0;
    Vec3 slice_wi(std::size_t slice) const { return spherical_direction(theta_i[slice % nT], phi_i[slice / nT]); }
};

// W1: the NDF table, from the options' NDF or by power iteration on the retro-reflection.
NodeTable ndf_nodes_of(const Acquisition& a) {
    const RglWriterOptions& options = a.options;
    const bool iso = a.iso;
    const std::string& path = a.path;
    NodeTable ndf_nodes;
    ndf_nodes.rows = iso ? 2 : options.ndf_rows;
    ndf_nodes.cols = options.ndf_size;
    ndf_nodes.values.assign(std::size_t(ndf_nodes.rows) * ndf_nodes.cols, 0.f);
    if (options.ndf) {
        for (int r = 0; r < ndf_nodes.rows; ++r)
            for (int c = 0; c < ndf_nodes.cols; ++c)
                ndf_nodes.values[std::size_t(r) * ndf_nodes.cols + c] =
                    std::max(0.f, options.ndf(node_direction(ndf_nodes.u_theta(c), iso ? 0.5f : ndf_nodes.u_phi(r), 0.f)));
    } else {
        ndf_nodes = ndf_by_power_iteration(a.source, a.query, a.luminance, ndf_nodes, options.power_iterations);
    }
    if (iso) {  // both rows equal: the relative azimuth carries no information
        for (int c = 0; c < ndf_nodes.cols; ++c) {
            const float v = 0.5f * (ndf_nodes.values[std::size_t(c)] + ndf_nodes.values[std::size_t(ndf_nodes.cols + c)]);
            ndf_nodes.values[std::size_t(c)] = ndf_nodes.values[std::size_t(ndf_nodes.cols + c)] = v;
        }
    }
    // A floor of 1e-4 of the peak (measured best of 1e-5..1e-2, docs/synth.md) keeps D > 0 everywhere, so that non-specular parts of the BRDF do not land
    // where the VNDF warp never goes and R = f cos 4 sigma / D does not blow up.
    const float ndf_max = *std::max_element(ndf_nodes.values.begin(), ndf_nodes.values.end());
    if (!(ndf_max > 0.f) || !std::isfinite(ndf_max)) throw Error(path, "the source's normal distribution is zero or not finite");
    for (float& v : ndf_nodes.values) v = std::isfinite(v) ? v + 1e-4f * ndf_max : ndf_max;
    return ndf_nodes;
}

// W2: sigma at the NDF's nodes, and the NDF normalised so that the integral of D cos is 1.
NodeTable sigma_nodes_of(const Acquisition& a, NodeTable& ndf_nodes, const std::function<void(double)>& progress) {
    const bool iso = a.iso;
    const std::string& path = a.path;
    NodeTable sigma_nodes = ndf_nodes;
    {
        PiecewiseLinear2D ndf_table(std::size_t(ndf_nodes.cols), std::size_t(ndf_nodes.rows), 1, ndf_nodes.values, false, path);
        const ProjectedAreaIntegrator sigma(ndf_table, ndf_nodes.rows, ndf_nodes.cols, iso);
        const double normal = sigma(Vec3(0.f, 0.f, 1.f));
        if (!(normal > 0.0)) throw Error(path, "the normal distribution integrates to zero");
        const int sigma_rows = iso ? 1 : sigma_nodes.rows;
        std::vector<double> raw(std::size_t(sigma_rows) * sigma_nodes.cols);
        npf::parallel_for(raw.size(), [&](std::size_t i) {
            const int r = int(i) / sigma_nodes.cols, c = int(i) % sigma_nodes.cols;
            const Vec3 w = node_direction(sigma_nodes.u_theta(c), iso ? 0.5f : sigma_nodes.u_phi(r), 0.f);
            raw[i] = sigma(w);
        }, a.threads, progress);
        for (int r = 0; r < sigma_nodes.rows; ++r)
            for (int c = 0; c < sigma_nodes.cols; ++c)
                sigma_nodes.values[std::size_t(r) * sigma_nodes.cols + c] =
                    float(raw[std::size_t(iso ? 0 : r) * sigma_nodes.cols + c] / normal);
        for (float& v : ndf_nodes.values) v = float(double(v) / normal);
    }
    return sigma_nodes;
}

// W3: the theta_i grid, equal steps in (azimuth-averaged) projected area.
std::vector<float> theta_grid(const NodeTable& sigma_nodes, const RglWriterOptions& options) {
    std::vector<double> mean_sigma(std::size_t(sigma_nodes.cols), 0.0);
    for (int r = 0; r < sigma_nodes.rows; ++r)
        for (int c = 0; c < sigma_nodes.cols; ++c)
            mean_sigma[std::size_t(c)] += sigma_nodes.values[std::size_t(r) * sigma_nodes.cols + c] / sigma_nodes.rows;
    // sigma = cos(theta) (1 + Lambda) can rise slightly just off the normal (rough lobes);
    // the rule needs it non-increasing, so it runs on the running minimum.
    for (std::size_t c = 1; c < mean_sigma.size(); ++c) mean_sigma[c] = std::min(mean_sigma[c], mean_sigma[c - 1]);
    const bool usable = mean_sigma.back() < 0.99 * mean_sigma.front();
    std::vector<float> theta_i(std::size_t(options.theta_count));
    for (int k = 0; k < options.theta_count; ++k) {
        const double f = double(k) / double(options.theta_count - 1);
        if (!usable) {  // no fall-off to divide into equal steps: equal steps in angle
            theta_i[std::size_t(k)] = float(f * 0.5 * kPiD);
            continue;
        }
        const double target = mean_sigma.front() + f * (mean_sigma.back() - mean_sigma.front());
        std::size_t c = 0;
        while (c + 2 < mean_sigma.size() && mean_sigma[c + 1] > target) ++c;
        const double drop = mean_sigma[c] - mean_sigma[c + 1];
        const double t = drop > 0.0 ? std::clamp((mean_sigma[c] - target) / drop, 0.0, 1.0) : 0.0;
        const double u = (double(c) + t) / double(mean_sigma.size() - 1);
        theta_i[std::size_t(k)] = u_to_theta(float(u));
    }
    theta_i.front() = 0.f;
    theta_i.back() = 0.5f * kPi;
    for (std::size_t k = 1; k < theta_i.size(); ++k) {  // keep it strictly ascending
        if (!(theta_i[k] > theta_i[k - 1])) theta_i[k] = std::nextafter(theta_i[k - 1], 2.f);
    }
    return theta_i;
}

std::vector<float> phi_grid(bool iso, const RglWriterOptions& options) {
    std::vector<float> phi_i;
    if (iso) {
        phi_i = {0.f};
    } else {
        for (int k = 0; k < options.phi_count; ++k) phi_i.push_back(-kPi + 2.f * kPi * float(k) / float(options.phi_count - 1));
    }
    return phi_i;
}

// W4: the VNDF of every slice.
std::vector<float> vndf_values_of(const Acquisition& a, const PiecewiseLinear2D& ndf, const PiecewiseLinear2D& sigma) {
    const bool iso = a.iso;
    const std::vector<float>& phi_i = a.phi_i;
    const std::vector<float>& theta_i = a.theta_i;
    const std::size_t nT = a.nT, slices = a.slices;
    const std::size_t V = std::size_t(a.options.vndf_size);
    std::vector<float> vndf_values(slices * V * V);
    npf::parallel_for(slices, [&](std::size_t slice) {
        const Vec3 wi = a.slice_wi(slice);
        const float phi_offset = iso ? phi_i[slice / nT] : 0.f;
        const float s_i = sigma.eval({theta_to_u(theta_i[slice % nT]), phi_to_u(phi_i[slice / nT])}, SliceBlend());
        float* out = vndf_values.data() + slice * V * V;
        float largest = 0.f;
        for (std::size_t r = 0; r < V; ++r) {
            for (std::size_t c = 0; c < V; ++c) {
                const float ux = float(c) / float(V - 1), uy = float(r) / float(V - 1);
                const Vec3 m = node_direction(ux, uy, phi_offset);
                const float d = ndf.eval({ux, uy}, SliceBlend());
                const float v = std::max(0.f, dot(wi, m)) * d / s_i * 2.f * kPi * kPi * ux * std::sin(u_to_theta(ux));
                out[r * V + c] = v;
                largest = std::max(largest, v);
            }
        }
        // Every slice needs a positive total (readers divide by it); a faint floor also keeps
        // the warp defined where wi.m <= 0.
        const float floor = largest > 0.f ? 1e-7f * largest : 1.f;
        for (std::size_t k = 0; k < V * V; ++k) out[k] += floor;
    }, a.threads);
    return vndf_values;
}

struct DataTables {
    std::vector<float> data, lum;
    std::vector<std::uint8_t> valid;
};

// W5: the data (R = f cos 4 sigma / D at the VNDF's samples) and their luminance.
DataTables data_tables_of(const Acquisition& a, const PiecewiseLinear2D& ndf, const PiecewiseLinear2D& sigma,
                          const PiecewiseLinear2D& vndf, const std::function<void(double)>& progress) {
    const bool iso = a.iso;
    const std::vector<float>& phi_i = a.phi_i;
    const std::size_t nT = a.nT, slices = a.slices;
    const std::size_t S = std::size_t(a.options.data_size);
    const std::size_t C = a.query.size();
    DataTables tables;
    std::vector<float>& data = tables.data;
    std::vector<float>& lum = tables.lum;
    std::vector<std::uint8_t>& valid = tables.valid;
    data.assign(slices * C * S * S, 0.f);
    lum.assign(slices * S * S, 0.f);
    valid.assign(slices * S * S, 0);
    npf::parallel_for(slices, [&](std::size_t slice) {
        const std::size_t p = slice / nT, t = slice % nT;
        const Vec3 wi = a.slice_wi(slice);
        const Vec3 wi_eval = lifted(wi);
        SliceBlend on_slice;
        on_slice.slice[0] = std::uint32_t(slice);
        const float phi_wi = azimuth(wi);
        const float s_i = sigma.eval({theta_to_u(elevation(wi)), phi_to_u(phi_wi)}, SliceBlend());
        std::vector<float> values(C);
        for (std::size_t r = 0; r < S; ++r) {
            for (std::size_t c = 0; c < S; ++c) {
                const Vec2 xi{float(c) / float(S - 1), float(r) / float(S - 1)};
                const Vec2 u_h = vndf.sample(xi, on_slice, nullptr);
                const Vec3 wh = spherical_direction(u_to_theta(u_h.x), u_to_phi(u_h.y) + (iso ? phi_i[p] : 0.f));
                const Vec3 wo = wh * (2.f * dot(wi, wh)) - wi;
                const std::size_t node = (slice * S + r) * S + c;
                if (!(wo.z > 0.f)) continue;  // R = 0, not valid
                valid[node] = 1;
                // The u-coordinate a reader computes from this half vector.
                const Vec3 h = normalize(wi + wo);
                float u_phi = phi_to_u(azimuth(h) - (iso ? phi_wi : 0.f));
                u_phi -= std::floor(u_phi);
                const float d = ndf.eval({theta_to_u(elevation(h)), u_phi}, SliceBlend());
                a.source.eval_cos(wi_eval, wo, a.query, values.data());
                const float ratio = d > 0.f ? 4.f * s_i / d : 0.f;
                for (std::size_t k = 0; k < C; ++k) {
                    data[((slice * C + k) * S + r) * S + c] = values[k] * ratio;
                    values[k] *= ratio;
                }
                lum[node] = float(std::max(0.0, a.luminance(values.data())));
            }
        }
        // Readers normalise each luminance slice and divide by its total: keep it positive,
        // with a floor so that every valid node stays reachable by sampling.
        float* l = lum.data() + slice * S * S;
        const float largest = *std::max_element(l, l + S * S);
        for (std::size_t k = 0; k < S * S; ++k) l[k] = largest > 0.f ? std::max(l[k], 1e-4f * largest) : 1.f;
        (void)t;
    }, a.threads, progress);

    return tables;
}

}  // namespace

bool looks_isotropic(const Brdf& source, int pairs, double tolerance) {
    const Channels channels = source.info().channels;
    ChannelQuery query = source.query(channels);
    const std::size_t n = std::min<std::size_t>(query.size(), 3);
    std::vector<float> a(query.size()), b(query.size());
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    auto direction = [&] {
        return spherical_direction(std::acos(0.02f + 0.97f * uni(rng)), 2.f * kPi * uni(rng) - kPi);
    };
    auto rotate = [](const Vec3& w, float angle) {
        const float c = std::cos(angle), s = std::sin(angle);
        return Vec3(c * w.x - s * w.y, s * w.x + c * w.y, w.z);
    };
    double largest = 0.0;
    std::vector<std::array<double, 2>> seen;
    for (int i = 0; i < pairs; ++i) {
        const Vec3 wi = direction(), wo = direction();
        const float angle = 2.f * kPi * uni(rng);
        source.eval_cos(wi, wo, query, a.data());
        source.eval_cos(rotate(wi, angle), rotate(wo, angle), query, b.data());
        for (std::size_t k = 0; k < n; ++k) {
            largest = std::max({largest, std::fabs(double(a[k])), std::fabs(double(b[k]))});
            seen.push_back({double(a[k]), double(b[k])});
        }
    }
    for (const auto& [x, y] : seen) {
        const double m = std::max(std::fabs(x), std::fabs(y));
        if (m <= 1e-6 * largest) continue;
        if (std::fabs(x - y) > tolerance * m) return false;
    }
    return true;
}

RglWriteReport write_rgl(const Brdf& source, const std::string& path, const RglWriterOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    check_options(options, path);
    Acquisition a{source, options, path, source.query(options.channels), LuminanceWeights(options.channels),
                  npf::thread_count(options.threads), false, {}, {}};
    a.iso = options.anisotropy == AnisotropyMode::Isotropic ||
            (options.anisotropy == AnisotropyMode::Auto && looks_isotropic(source));
    const bool iso = a.iso;

    RglWriteReport report;
    report.path = path;
    report.isotropic = iso;

    // Progress: 10% for the NDF and sigma, the rest for the slices.
    auto stage = [&options](double begin, double span) -> std::function<void(double)> {
        return [&options, begin, span](double f) {
            if (options.progress) options.progress(begin + span * f);
        };
    };

    NodeTable ndf_nodes = ndf_nodes_of(a);
    stage(0.0, 0.1)(0.03);
    const NodeTable sigma_nodes = sigma_nodes_of(a, ndf_nodes, stage(0.03, 0.07));
    const PiecewiseLinear2D ndf(std::size_t(ndf_nodes.cols), std::size_t(ndf_nodes.rows), 1, ndf_nodes.values, false, path);
    const PiecewiseLinear2D sigma(std::size_t(sigma_nodes.cols), std::size_t(sigma_nodes.rows), 1, sigma_nodes.values,
                                  false, path);
    a.theta_i = theta_grid(sigma_nodes, options);
    a.phi_i = phi_grid(iso, options);
    a.nP = a.phi_i.size();
    a.nT = a.theta_i.size();
    a.slices = a.nP * a.nT;
    const std::vector<float>& phi_i = a.phi_i;
    const std::vector<float>& theta_i = a.theta_i;
    const std::size_t nP = a.nP, nT = a.nT;
    const std::size_t V = std::size_t(options.vndf_size), S = std::size_t(options.data_size);
    const std::vector<float> vndf_values = vndf_values_of(a, ndf, sigma);
    const PiecewiseLinear2D vndf(V, V, a.slices, vndf_values, true, path);
    const DataTables tables = data_tables_of(a, ndf, sigma, vndf, stage(0.1, 0.9));
    const std::vector<float>& data = tables.data;
    const std::vector<float>& lum = tables.lum;
    const std::vector<std::uint8_t>& valid = tables.valid;
    const std::size_t C = a.query.size();

    // ---- W6: the file. ---------------------------------------------------------------------
    TensorFileWriter writer;
    const BrdfInfo& info = source.info();
    std::string description = options.description.empty() ? info.description : options.description;
    if (description.empty()) description = "npf virtual acquisition of a " + info.format + " material";
    writer.add_string("description", description);
    writer.add_u8("jacobian", {1}, {1});
    writer.add_f32("phi_i", shape({nP}), phi_i);
    writer.add_f32("theta_i", shape({nT}), theta_i);
    writer.add_f32("ndf", shape({std::size_t(ndf_nodes.rows), std::size_t(ndf_nodes.cols)}), ndf_nodes.values);
    writer.add_f32("sigma", shape({std::size_t(sigma_nodes.rows), std::size_t(sigma_nodes.cols)}), sigma_nodes.values);
    writer.add_f32("vndf", shape({nP, nT, V, V}), vndf_values);
    writer.add_f32("luminance", shape({nP, nT, S, S}), lum);
    if (options.channels.is_rgb()) {
        writer.add_f32("rgb", shape({nP, nT, 3, S, S}), data);
    } else {
        writer.add_f32("wavelengths", shape({C}), options.channels.wavelengths());
        writer.add_f32("spectra", shape({nP, nT, C, S, S}), data);
    }
    std::vector<std::uint8_t> packed((valid.size() + 7) / 8, 0);
    for (std::size_t i = 0; i < valid.size(); ++i) {
        if (valid[i]) packed[i / 8] |= std::uint8_t(0x80u >> (i % 8));
        report.valid_nodes += valid[i];
    }
    writer.add_u8("valid", shape({packed.size()}), packed);
    const std::vector<std::uint8_t> bytes = writer.serialize();
    write_file_atomically(path, bytes.data(), bytes.size());

    report.bytes = bytes.size();
    report.theta_i = theta_i;
    report.phi_i = phi_i;
    report.data_nodes = valid.size();
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

}  // namespace npf
