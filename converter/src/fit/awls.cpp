#include <npf/converter/fit/awls.h>

#include <npf/core/error.h>
#include <npf/core/vec.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>

namespace npf {

namespace {

constexpr double kHalfPi = 0.5 * kPiD, kTwoPi = 2.0 * kPiD;

// Everything about a grid sample that does not depend on the channel: computed once.
struct Sample {
    std::uint32_t d;       // D cell
    std::uint32_t gi, go;  // G cells of wi and wo
    std::uint16_t f;       // F cell
    float geometry;        // w_V w_I
    float inv_cc;          // 1 / (cos theta_i cos theta_o)
};

int g_theta_cell(double z, int n) {
    const double theta = std::acos(std::clamp(z, -1.0, 1.0));
    return std::min(int(theta / kHalfPi * n), n - 1);
}

int g_phi_cell(double x, double y, int n) {
    if (n == 1) return 0;
    double phi = std::atan2(y, x);
    if (phi < 0.0) phi += kTwoPi;
    return std::min(int(phi / kTwoPi * n), n - 1);
}

// Runs body(t, begin, end) on `threads` contiguous slices of [0, count).
template <typename Body>
void split(std::size_t count, int threads, Body body) {
    std::vector<std::thread> pool;
    std::exception_ptr failure;
    std::mutex m;
    for (int t = 0; t < threads; ++t) {
        const std::size_t b = count * std::size_t(t) / std::size_t(threads), e = count * std::size_t(t + 1) / std::size_t(threads);
        auto run = [&, t, b, e] {
            try {
                body(t, b, e);
            } catch (...) {
                std::lock_guard<std::mutex> lock(m);
                if (!failure) failure = std::current_exception();
            }
        };
        if (t + 1 == threads) run();
        else pool.emplace_back(run);
    }
    for (std::thread& th : pool) th.join();
    if (failure) std::rethrow_exception(failure);
}

// One channel's factors during the fit, in double.
struct Factors {
    double rho_d = 0.0, rho_s = 1.0;
    std::vector<double> D, F, G;
};

class ChannelFit {
public:
    ChannelFit(const std::vector<Sample>& samples, const float* rho, std::size_t stride, const AwlsOptions& o)
        : m_samples(samples), m_rho(rho), m_stride(stride), m_o(o) {
        m_w.resize(samples.size());
        for (std::size_t s = 0; s < samples.size(); ++s) {
            double w = samples[s].geometry;
            if (o.compressive_power != 0.0) {
                w *= std::pow(std::max(0.0, double(value(s))) + o.compressive_epsilon, -o.compressive_power);
            }
            m_w[s] = w;
        }
    }

    float value(std::size_t s) const { return m_rho[s * m_stride]; }

    double model(const Factors& f, std::size_t s) const {
        const Sample& p = m_samples[s];
        return f.rho_d + f.rho_s * f.D[p.d] * f.F[p.f] * f.G[p.gi] * f.G[p.go] * p.inv_cc;
    }

    double error(const Factors& f, double* reference = nullptr) const {
        double e = 0.0, r = 0.0;
        for (std::size_t s = 0; s < m_samples.size(); ++s) {
            const double d = value(s) - model(f, s);
            e += m_w[s] * d * d;
            r += m_w[s] * double(value(s)) * value(s);
        }
        if (reference) *reference = r;
        return e;
    }

    // Closed-form update of one table: cell k = sum w a b / sum w b^2 over its samples (Eq. 10),
    // with a = rho - rho_d and b the rest of the product; cells without weight keep their value.
    template <typename Cell, typename Coefficient>
    void update(std::vector<double>& table, Cell cell, Coefficient coefficient, const Factors& f) const {
        std::vector<double> num(table.size(), 0.0), den(table.size(), 0.0);
        for (std::size_t s = 0; s < m_samples.size(); ++s) {
            const double b = coefficient(m_samples[s]);
            const double a = value(s) - f.rho_d;
            const std::size_t k = cell(m_samples[s]);
            num[k] += m_w[s] * a * b;
            den[k] += m_w[s] * b * b;
        }
        for (std::size_t k = 0; k < table.size(); ++k) {
            if (den[k] > 1e-300) table[k] = std::max(0.0, num[k] / den[k]);
        }
    }

    // D and rho_d together: a constant rho_d and the tail of D explain the same samples, and
    // alternating between them converges slowly. Every sample lies in exactly one D cell, so
    // the joint least-squares problem has a closed form: eliminate each D_k, solve the scalar
    // equation for rho_d, then back-substitute (both clamped at 0).
    void update_d_and_diffuse(Factors& f) const {
        const std::size_t n = f.D.size();
        std::vector<double> wb(n, 0.0), wbb(n, 0.0), wrb(n, 0.0);
        double w_sum = 0.0, wr_sum = 0.0;
        for (std::size_t s = 0; s < m_samples.size(); ++s) {
            const Sample& p = m_samples[s];
            const double b = f.rho_s * f.F[p.f] * f.G[p.gi] * f.G[p.go] * p.inv_cc;
            const double w = m_w[s], r = value(s);
            wb[p.d] += w * b;
            wbb[p.d] += w * b * b;
            wrb[p.d] += w * r * b;
            w_sum += w;
            wr_sum += w * r;
        }
        double num = wr_sum, den = w_sum;
        for (std::size_t k = 0; k < n; ++k) {
            if (wbb[k] <= 1e-300) continue;
            num -= wb[k] * wrb[k] / wbb[k];
            den -= wb[k] * wb[k] / wbb[k];
        }
        f.rho_d = den > 1e-12 * w_sum ? std::max(0.0, num / den) : 0.0;
        for (std::size_t k = 0; k < n; ++k) {
            if (wbb[k] > 1e-300) f.D[k] = std::max(0.0, (wrb[k] - f.rho_d * wb[k]) / wbb[k]);
        }
    }

    void iterate(Factors& f) const {
        const auto& D = f.D;
        const auto& F = f.F;
        const auto& G = f.G;
        if (f.rho_s > 0.0) {
            update_d_and_diffuse(f);
            update(f.F, [](const Sample& p) { return p.f; },
                   [&](const Sample& p) { return f.rho_s * D[p.d] * G[p.gi] * G[p.go] * p.inv_cc; }, f);
            update_g(f);
        }
        // rho_d: the weighted mean of what the specular part leaves.
        double num = 0.0, den = 0.0;
        for (std::size_t s = 0; s < m_samples.size(); ++s) {
            const Sample& p = m_samples[s];
            num += m_w[s] * (value(s) - f.rho_s * D[p.d] * F[p.f] * G[p.gi] * G[p.go] * p.inv_cc);
            den += m_w[s];
        }
        f.rho_d = den > 0.0 ? std::max(0.0, num / den) : 0.0;
        // rho_s.
        num = den = 0.0;
        for (std::size_t s = 0; s < m_samples.size(); ++s) {
            const Sample& p = m_samples[s];
            const double b = D[p.d] * F[p.f] * G[p.gi] * G[p.go] * p.inv_cc;
            num += m_w[s] * (value(s) - f.rho_d) * b;
            den += m_w[s] * b * b;
        }
        f.rho_s = den > 0.0 ? std::max(0.0, num / den) : 0.0;
    }

    // G appears twice per sample: each sample updates the cell of wi with the other copy held
    // at its previous value, and the cell of wo likewise (reciprocity); the result is damped
    // by half, which keeps the alternation from oscillating between the two copies.
    void update_g(Factors& f) const {
        std::vector<double> num(f.G.size(), 0.0), den(f.G.size(), 0.0);
        for (std::size_t s = 0; s < m_samples.size(); ++s) {
            const Sample& p = m_samples[s];
            const double common = f.rho_s * f.D[p.d] * f.F[p.f] * p.inv_cc;
            const double a = value(s) - f.rho_d;
            const double bi = common * f.G[p.go], bo = common * f.G[p.gi];
            num[p.gi] += m_w[s] * a * bi;
            den[p.gi] += m_w[s] * bi * bi;
            num[p.go] += m_w[s] * a * bo;
            den[p.go] += m_w[s] * bo * bo;
        }
        for (std::size_t k = 0; k < f.G.size(); ++k) {
            if (den[k] > 1e-300) f.G[k] = 0.5 * (f.G[k] + std::max(0.0, num[k] / den[k]));
        }
    }

private:
    const std::vector<Sample>& m_samples;
    const float* m_rho;
    std::size_t m_stride;
    const AwlsOptions& m_o;
    std::vector<double> m_w;
};

// Fixes the scale ambiguities without changing the model: projected area of D = 1, G = 1 at
// normal incidence, F = 1 at theta_d = 0.
void normalise(Factors& f, const RusinkiewiczGrid& grid, int g_phi) {
    double area = 0.0;
    const double du = 1.0 / grid.theta_h, dphi = kTwoPi / grid.phi_h;
    for (int i = 0; i < grid.theta_h; ++i) {
        const double u = (i + 0.5) * du, th = grid.theta_h_at(i);
        for (int j = 0; j < grid.phi_h; ++j) area += f.D[std::size_t(i) * grid.phi_h + j] * std::cos(th) * std::sin(th) * kPiD * u * du * dphi;
    }
    if (area > 0.0) {
        for (double& v : f.D) v /= area;
        f.rho_s *= area;
    }
    double g0 = 0.0;
    for (int j = 0; j < g_phi; ++j) g0 += f.G[std::size_t(j)] / g_phi;
    if (g0 > 0.0) {
        for (double& v : f.G) v /= g0;
        f.rho_s *= g0 * g0;
    }
    if (f.F[0] > 0.0) {
        const double f0 = f.F[0];
        for (double& v : f.F) v /= f0;
        f.rho_s *= f0;
    }
}

}  // namespace

NpfFactors fit_npf(const Brdf& source, const AwlsOptions& o, AwlsReport* report) {
    const auto start = std::chrono::steady_clock::now();
    const RusinkiewiczGrid& grid = o.grid;
    if (grid.theta_h < 2 || grid.phi_h < 1 || grid.theta_d < 2 || grid.phi_d < 2 || o.g_theta < 2 || o.g_phi < 1 ||
        grid.theta_d > 65535) {
        throw Error("fit", "grid sizes must be at least 2 (phi_h and the G phi cells at least 1)");
    }
    const ChannelQuery query = source.query(o.channels);
    const std::size_t C = query.size();
    const int threads = o.threads > 0 ? o.threads : int(std::max(1u, std::thread::hardware_concurrency()));

    // ---- Geometry of every grid sample with both directions above the horizon. ----------
    std::vector<Sample> samples;
    std::vector<Vec3d> wis, wos;
    for (int ih = 0; ih < grid.theta_h; ++ih) {
        for (int jh = 0; jh < grid.phi_h; ++jh) {
            for (int id = 0; id < grid.theta_d; ++id) {
                const double wv = grid.volume_weight(ih, id);
                for (int jd = 0; jd < grid.phi_d; ++jd) {
                    const HalfDiff a{grid.theta_h_at(ih), grid.phi_h_at(jh), grid.theta_d_at(id), grid.phi_d_at(jd)};
                    Vec3d wi, wo;
                    directions_from_half_diff(a, wi, wo);
                    if (!(wi.z > 1e-6) || !(wo.z > 1e-6)) continue;
                    Sample s;
                    s.d = std::uint32_t(ih * grid.phi_h + jh);
                    s.f = std::uint16_t(id);
                    s.gi = std::uint32_t(g_theta_cell(wi.z, o.g_theta) * o.g_phi + g_phi_cell(wi.x, wi.y, o.g_phi));
                    s.go = std::uint32_t(g_theta_cell(wo.z, o.g_theta) * o.g_phi + g_phi_cell(wo.x, wo.y, o.g_phi));
                    s.geometry = float(wv * std::pow(wi.z * wo.z, o.importance_power));
                    s.inv_cc = float(1.0 / (wi.z * wo.z));
                    samples.push_back(s);
                    wis.push_back(wi);
                    wos.push_back(wo);
                }
            }
        }
    }
    if (samples.empty()) throw Error("fit", "the grid has no sample with both directions above the horizon");

    // ---- Resampling: rho = f cos / cos(theta_o) for every channel, on all threads. -------------
    std::vector<float> rho(samples.size() * C);
    std::atomic<std::size_t> done{0};
    split(samples.size(), threads, [&](int t, std::size_t b, std::size_t e) {
        std::vector<float> v(C);
        for (std::size_t s = b; s < e; ++s) {
            const Vec3 wi(float(wis[s].x), float(wis[s].y), float(wis[s].z)), wo(float(wos[s].x), float(wos[s].y), float(wos[s].z));
            source.eval_cos(wi, wo, query, v.data());
            for (std::size_t c = 0; c < C; ++c) {
                const float r = wo.z > 0.f ? v[c] / wo.z : 0.f;
                rho[s * C + c] = std::isfinite(r) ? r : 0.f;
            }
            if (t == 0 && o.progress && (s - b) % 65536 == 0) o.progress(0.3 * double(s - b) / double(e - b));
        }
        done += e - b;
    });

    // ---- AWLS, channel by channel; each thread takes a block of channels and starts every
    // channel from its neighbour's converged factors. ------------------------------------------
    NpfFactors out;
    out.grid = grid;
    out.g_theta = o.g_theta;
    out.g_phi = o.g_phi;
    out.channels = o.channels;
    out.rho_d.assign(C, 0.f);
    out.rho_s.assign(C, 0.f);
    out.D.assign(C * out.d_size(), 0.f);
    out.F.assign(C * std::size_t(grid.theta_d), 0.f);
    out.G.assign(C * out.g_size(), 0.f);
    std::vector<int> iterations(C, 0);
    std::vector<double> errors(C, 0.0);
    std::atomic<std::size_t> channels_done{0};
    split(C, std::min<int>(threads, int(C)), [&](int t, std::size_t b, std::size_t e) {
        Factors f;
        for (std::size_t c = b; c < e; ++c) {
            ChannelFit fit(samples, rho.data() + c, C, o);
            if (c == b) {  // a cold start: flat F and G, D from the first update, no diffuse
                f.rho_d = 0.0;
                f.rho_s = 1.0;
                f.D.assign(out.d_size(), 1.0);
                f.F.assign(std::size_t(grid.theta_d), 1.0);
                f.G.assign(out.g_size(), 1.0);
            }
            double reference = 0.0;
            double previous = fit.error(f, &reference);
            int it = 0;
            for (; it < o.max_iterations; ++it) {
                fit.iterate(f);
                normalise(f, grid, o.g_phi);
                const double e_now = fit.error(f);
                const bool converged = previous - e_now <= o.tolerance * previous;
                previous = e_now;
                if (converged) break;
            }
            iterations[c] = it + 1;
            errors[c] = reference > 0.0 ? std::sqrt(previous / reference) : 0.0;
            out.rho_d[c] = float(f.rho_d);
            out.rho_s[c] = float(f.rho_s);
            std::transform(f.D.begin(), f.D.end(), out.D.begin() + long(c * out.d_size()), [](double v) { return float(v); });
            std::transform(f.F.begin(), f.F.end(), out.F.begin() + long(c * std::size_t(grid.theta_d)),
                           [](double v) { return float(v); });
            std::transform(f.G.begin(), f.G.end(), out.G.begin() + long(c * out.g_size()), [](double v) { return float(v); });
            const std::size_t n = ++channels_done;
            if (t == 0 && o.progress) o.progress(0.3 + 0.7 * double(n) / double(C));
        }
    });
    if (o.progress) o.progress(1.0);
    if (report) {
        report->samples = samples.size();
        report->iterations = iterations;
        report->relative_error = errors;
        report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return out;
}

}  // namespace npf
