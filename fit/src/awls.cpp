#include <npf/fit/awls.h>

#include "block_fit.h"
#include "sample_set.h"

#include <npf/core/error.h>
#include <npf/core/parallel.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace npf {

namespace {

using Clock = std::chrono::steady_clock;

// The most memory that source values evaluated ahead of their blocks may take: on the production
// anisotropic grid (8.8 M samples, 0.56 GB per block of 16) three blocks, so that 195 wavelengths
// take 5 passes over the source instead of 13, and the brushed copper conversion peaks at
// 3.49 GiB (the samples 0.5 GB, the block's data and weights 1.1 GB, these 1.7 GB, the source
// file). A pass costs little more than its channels: the RGL reader interpolates only the
// stored channels a pass reads.
constexpr std::size_t kResampleBytes = std::size_t(7) << 28;  // 1.75 GiB

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void check_options(const AwlsOptions& o) {
    namespace lim = awls_limits;
    const RusinkiewiczGrid& g = o.grid;
    const int sizes[6] = {g.theta_h, g.phi_h, g.theta_d, g.phi_d, o.g_theta, o.g_phi};
    const bool phi_axis[6] = {false, true, false, false, false, true};
    for (int i = 0; i < 6; ++i) {
        if (sizes[i] < (phi_axis[i] ? lim::kMinPhiCells : lim::kMinCells) || sizes[i] > lim::kMaxCells) {
            throw Error("fit", "grid sizes must lie in " + std::to_string(lim::kMinCells) + ".." + std::to_string(lim::kMaxCells) +
                                   " (phi_h and the G phi cells from " + std::to_string(lim::kMinPhiCells) + ")");
        }
    }
    if (o.phi_d_samples < 0 || o.phi_d_samples > lim::kMaxPhiDSamples)
        throw Error("fit", "phi_d samples must lie in 0.." + std::to_string(lim::kMaxPhiDSamples));
    if (o.max_iterations < 1 || o.max_iterations > lim::kMaxIterations || !(o.tolerance >= 0.0) || !std::isfinite(o.tolerance))
        throw Error("fit", "need 1.." + std::to_string(lim::kMaxIterations) + " iterations and a finite tolerance >= 0");
    if (!std::isfinite(o.importance_power_view) || !std::isfinite(o.importance_power_light) || !std::isfinite(o.compressive_power) ||
        !(o.compressive_epsilon > 0.0) || !std::isfinite(o.compressive_epsilon)) {
        throw Error("fit", "weight powers must be finite and the compressive epsilon positive");
    }
    if (!(o.g_pin >= 0.0) || !std::isfinite(o.g_pin)) throw Error("fit", "the G pin must be finite and >= 0");
}

// The channels of block b: RGB is one block; wavelengths go L at a time.
Channels block_channels(const Channels& all, std::size_t begin, std::size_t end) {
    if (all.is_rgb()) return all;
    return Channels::spectral(std::vector<float>(all.wavelengths().begin() + long(begin), all.wavelengths().begin() + long(end)));
}

template <int L>
void fit_blocks(const Brdf& source, const AwlsOptions& o, const fit_detail::SampleSet& samples, int threads, NpfFactors& out,
                AwlsReport& report) {
    const std::size_t C = out.channel_count();
    const std::size_t blocks = (C + L - 1) / L;
    fit_detail::BlockFit<L> fit(samples, o, threads);
    fit_detail::BlockFactors<L> f;
    const auto expected = double(std::max(o.max_iterations / 4, 1));  // for the progress estimate
    // The source is evaluated for several blocks at once (BlockFit::evaluate), as many as fit in
    // kResampleBytes, spread evenly over the passes.
    const std::size_t block_bytes = std::max<std::size_t>(1, samples.size() * L * sizeof(float));
    const std::size_t max_group = std::max<std::size_t>(1, kResampleBytes / block_bytes);
    std::vector<std::vector<float>> pending;  // values of blocks [group_begin, group_end)
    std::size_t group_begin = 0, group_end = 0;
    for (std::size_t b = 0; b < blocks; ++b) {
        const std::size_t c0 = b * L, c1 = std::min(C, c0 + L);
        auto t = Clock::now();
        if (b == group_end) {
            const std::size_t left = blocks - b, passes = (left + max_group - 1) / max_group;
            group_begin = b;
            group_end = b + (left + passes - 1) / passes;
            std::vector<Channels> group;
            for (std::size_t g = group_begin; g < group_end; ++g) group.push_back(block_channels(out.channels, g * L, std::min(C, g * L + L)));
            fit_detail::BlockFit<L>::evaluate(samples, source, group, threads, pending);
        }
        report.invalid_values += fit.load(pending[b - group_begin], c1 - c0);  // the old buffer comes back
        report.seconds_resampling += seconds_since(t);
        t = Clock::now();
        f = b == 0 ? fit.cold_start() : fit.warm_start(f, L - 1);
        std::array<double, L> error{};
        const int iterations = fit.run(f, b == 0, error, [&](int it) {
            if (o.progress) o.progress((double(b) + std::min(0.95, it / expected)) / double(blocks));
        });
        report.seconds_fitting += seconds_since(t);
        for (std::size_t c = c0; c < c1; ++c) {
            const std::size_t l = c - c0;
            report.iterations[c] = iterations;
            report.relative_error[c] = error[l];
            out.rho_d[c] = float(f.rho_d[l]);
            out.rho_s[c] = float(f.rho_s[l]);
            for (std::size_t k = 0; k < out.d_size(); ++k) out.D[c * out.d_size() + k] = f.D[k * L + l];
            for (std::size_t k = 0; k < std::size_t(out.grid.theta_d); ++k) out.F[c * std::size_t(out.grid.theta_d) + k] = f.F[k * L + l];
            for (std::size_t k = 0; k < out.g_size(); ++k) out.G[c * out.g_size() + k] = f.G[k * L + l];
        }
    }
}

}  // namespace

NpfFactors fit_npf(const Brdf& source, const AwlsOptions& o, AwlsReport* report) {
    const auto start = Clock::now();
    check_options(o);
    const std::size_t C = source.query(o.channels).size();  // throws when the source cannot give them
    const int threads = npf::thread_count(o.threads);

    AwlsReport r;
    auto t = Clock::now();
    const fit_detail::SampleSet samples = fit_detail::make_sample_set(o, threads);
    r.seconds_geometry = seconds_since(t);
    r.samples = samples.size();

    NpfFactors out;
    out.grid = o.grid;
    out.g_theta = o.g_theta;
    out.g_phi = o.g_phi;
    out.channels = o.channels;
    out.rho_d.assign(C, 0.f);
    out.rho_s.assign(C, 0.f);
    out.D.assign(C * out.d_size(), 0.f);
    out.F.assign(C * std::size_t(o.grid.theta_d), 0.f);
    out.G.assign(C * out.g_size(), 0.f);
    r.iterations.assign(C, 0);
    r.relative_error.assign(C, 0.0);
    if (C <= 4) fit_blocks<4>(source, o, samples, threads, out, r);
    else fit_blocks<16>(source, o, samples, threads, out, r);
    if (o.progress) o.progress(1.0);
    r.seconds = seconds_since(start);
    if (report) *report = r;
    return out;
}

}  // namespace npf
