#include <npf/fit/detail_fit.h>

#include "detail_steps.h"

#include <npf/fit/spectral_compression.h>
#include <npf/core/parallel.h>

#include <Imath/half.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace npf {

namespace {

using fit_detail::DetailSystem;

// The channels of one weight group are solved in this many chains of neighbouring channels (each
// channel of a chain starting from the previous one's solution, the first from 0), whatever the
// number of threads: the chains run in parallel and the result does not depend on the threads.
// (One chain left a 195-wavelength material's solves, a third of its detail fit, on one core.)
constexpr std::size_t kChainsPerGroup = 4;

const char* const kWhat = "detail layer";

// Each weight group's channels in order, cut into kChainsPerGroup chains.
std::vector<std::vector<std::size_t>> solve_chains(const DetailSystem& sys) {
    std::vector<std::vector<std::size_t>> chains;
    for (std::size_t gr = 0; gr < sys.groups; ++gr) {
        std::vector<std::size_t> members;
        for (std::size_t ch = 0; ch < sys.channels; ++ch) {
            if (sys.group_of(ch) == gr) members.push_back(ch);
        }
        const std::size_t count = std::min(kChainsPerGroup, members.size());
        for (std::size_t k = 0; k < count; ++k) {
            chains.emplace_back(members.begin() + long(k * members.size() / count),
                                members.begin() + long((k + 1) * members.size() / count));
        }
    }
    return chains;
}

// The channels' solutions across the passes.
struct ChannelSolves {
    std::vector<std::vector<double>> solution;  // [channels][cells]
    std::vector<float> tables;                  // [channels][cells], the solutions as stored
    std::vector<int> iterations;                // per channel, the most of any pass
};

// One pass: every channel solved for the right-hand sides `rhs`, the first pass from its
// chain's last channel, later ones from the last pass's solution.
void solve_pass(const DetailSystem& sys, const std::vector<std::vector<std::size_t>>& chains,
                const std::vector<std::vector<double>>& rhs, int pass, const DetailOptions& o, int threads, ChannelSolves& out) {
    const std::size_t cells = sys.cells;
    npf::parallel_for(chains.size(), [&](std::size_t k) {
        std::vector<double> x(cells, 0.0);
        for (std::size_t ch : chains[k]) {
            if (pass > 0) x = out.solution[ch];
            const fit_detail::NormalOperator op = fit_detail::NormalOperator::of(sys, ch);
            out.iterations[ch] = std::max(out.iterations[ch], fit_detail::solve(op, rhs[ch], x, o.max_iterations, o.tolerance));
            out.solution[ch] = x;
            for (std::size_t i = 0; i < cells; ++i) out.tables[ch * cells + i] = float(x[i]);
        }
    }, threads);
}

// Compresses the channels' tables across channels and stores them as the model's layer.
void store_layer(const std::vector<float>& tables, const DetailSystem& sys, const DetailOptions& o, NpfModel& model) {
    SpectralBasis basis = compress_tables(tables, sys.channels, sys.cells, o.ratio, o.rank, /*per_channel=*/true);
    if (o.half_precision) {
        for (float& v : basis.basis) v = float(Imath::half(v));
    }
    model.detail_grid = sys.grid;
    model.detail = std::move(basis);
}

// What the clamp max(0, NPF + r) adds at each view ([views][channels]): the stored layer's
// albedo, clamp included (`albedo`, by clamped_albedo), minus its linear part (the energy rows'
// own sums).
std::vector<double> clamp_gain(const DetailSystem& sys, const NpfModel& model, const std::vector<double>& albedo) {
    const std::size_t C = sys.channels;
    std::vector<double> gain = albedo;
    for (std::size_t v = 0; v < sys.views(); ++v) {
        for (std::size_t ch = 0; ch < C; ++ch) {
            double linear = sys.albedo_base[v * C + ch];
            for (std::size_t i = 0; i < sys.cells; ++i) linear += sys.rows[v][i] * model.detail.at(ch, i);
            gain[v * C + ch] -= linear;
        }
    }
    return gain;
}

// The largest change of the clamp's gain at any view and channel, relative to the source's albedo.
double largest_move(const DetailSystem& sys, const std::vector<double>& gain, const std::vector<double>& last_gain) {
    double moved = 0.0;
    for (std::size_t k = 0; k < gain.size(); ++k) {
        const double a = sys.albedo_source[k];
        if (a > 0.0) moved = std::max(moved, std::fabs(gain[k] - last_gain[k]) / a);
    }
    return moved;
}

// The right-hand sides with the energy rows' targets moved by the clamp's gain.
std::vector<std::vector<double>> shifted_targets(const DetailSystem& sys, const std::vector<double>& gain) {
    std::vector<std::vector<double>> rhs = sys.rhs;
    for (std::size_t ch = 0; ch < sys.channels; ++ch) {
        if (sys.row_weight[ch].empty()) continue;
        for (std::size_t v = 0; v < sys.views(); ++v) {
            const double shift = -sys.row_weight[ch][v] * gain[v * sys.channels + ch];
            if (shift == 0.0) continue;
            for (std::size_t i = 0; i < sys.cells; ++i) rhs[ch][i] += shift * sys.rows[v][i];
        }
    }
    return rhs;
}

// Fits the layer and stores it in `model`; the iterations (the most of any channel). Returns the
// stored layer's albedo at the views, clamp included, where the passes measured it (else empty).
//
// Each pass solves every channel from the last pass's solution. The first pass holds the
// energy rows' linear albedo; each later one moves their targets by what the clamp
// max(0, NPF + r) added at each view in the last pass (measured by the same quadrature), so
// that the albedo of the layer as stored, clamp included, meets the source's.
std::vector<double> fit_layer(const DetailSystem& sys, const DetailOptions& o, int threads,
                              const std::function<void(double)>& progress, NpfModel& model, int& iterations_max) {
    const std::size_t C = sys.channels, V = sys.views();
    const std::vector<std::vector<std::size_t>> chains = solve_chains(sys);
    ChannelSolves solves{std::vector<std::vector<double>>(C, std::vector<double>(sys.cells, 0.0)),
                         std::vector<float>(C * sys.cells, 0.f), std::vector<int>(C, 0)};
    std::vector<std::vector<double>> rhs = sys.rhs;
    std::vector<double> last_gain(V * C, 0.0);
    std::vector<double> albedo_after;
    for (int pass = 0;; ++pass) {
        solve_pass(sys, chains, rhs, pass, o, threads, solves);
        if (pass == 0 && progress) progress(0.8);
        store_layer(solves.tables, sys, o, model);
        if (pass >= o.clamp_passes || V == 0) break;
        albedo_after = fit_detail::clamped_albedo(sys, model, threads);
        const std::vector<double> gain = clamp_gain(sys, model, albedo_after);
        // Settled: the clamp's gain moved no albedo by more than 0.05 % since the last pass.
        if (largest_move(sys, gain, last_gain) < 5e-4) break;  // albedo_after is the stored layer's
        albedo_after.clear();
        last_gain = gain;
        rhs = shifted_targets(sys, gain);
    }
    for (int it : solves.iterations) iterations_max = std::max(iterations_max, it);
    return albedo_after;
}

// The data error sum w (f_model - f_source)^2 over sum w f_source^2, mean over channels, with the
// stored layer (clamp included) against the base model the system was assembled for.
double weighted_error_after(const DetailSystem& sys, const NpfModel& model, int threads) {
    const std::size_t C = sys.channels, groups = sys.groups, sh = sys.theta_h.angle.size();
    std::vector<double> error_after(sh * C, 0.0);
    npf::parallel_slices(sh, std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
        std::vector<double> with(C), without(C);
        for (std::size_t a = begin; a < end; ++a) {
            fit_detail::for_each_sample_of_row(sys, [&](int b, int c, int e) {
                const std::size_t s = sys.sample_index(a, b, c, e);
                if (!(sys.weight[s * groups] > 0.f)) return;
                Vec3d wi, wo;
                directions_from_half_diff(sys.sample_angles(a, b, c, e), wi, wo);
                // With and without the layer from one lookup (without it: the model the layer was
                // fitted to, the same tables, the same bits).
                NpfModel::Lookup at;
                if (model.prepare(fit_detail::to_float(wi), fit_detail::to_float(wo), at)) {
                    model.values(at, with.data(), without.data());
                } else {
                    std::fill(with.begin(), with.end(), 0.0);
                    std::fill(without.begin(), without.end(), 0.0);
                }
                for (std::size_t ch = 0; ch < C; ++ch) {
                    const double r = double(sys.residual[s * C + ch]) - (with[ch] - without[ch]);
                    error_after[a * C + ch] += double(sys.weight[s * groups + sys.group_of(ch)]) * r * r;
                }
            });
        }
    }, threads);
    double error = 0.0;
    for (std::size_t ch = 0; ch < C; ++ch) {
        double e = 0.0;
        for (std::size_t a = 0; a < sh; ++a) e += error_after[a * C + ch];
        error += sys.data_norm[ch] > 0.0 ? e / sys.data_norm[ch] / double(C) : 0.0;
    }
    return error;
}

}  // namespace

DetailReport fit_detail_layer(const Brdf& source, NpfModel& model, const DetailOptions& o,
                              const std::function<void(double)>& progress) {
    const auto start = std::chrono::steady_clock::now();
    fit_detail::check_detail_options(o);
    model.detail_grid = DetailGrid{};
    model.detail = SpectralBasis{};
    model.validate(kWhat);
    const int threads = npf::thread_count(o.threads);
    const DetailSystem sys = fit_detail::assemble_detail_system(source, model, o, threads, progress);
    const std::size_t C = sys.channels;

    DetailReport report;
    report.samples = sys.samples_valid;
    for (std::size_t ch = 0; ch < C; ++ch) {
        report.weighted_error_before += sys.data_norm[ch] > 0.0 ? sys.data_error[ch] / sys.data_norm[ch] / double(C) : 0.0;
    }
    report.energy_error_before = sys.energy_error(sys.albedo_base);

    std::vector<double> albedo_after = fit_layer(sys, o, threads, progress, model, report.iterations_max);
    model.validate(kWhat);

    // What the stored layer achieves, clamp included: the albedo it gives (npf albedo measures
    // it independently; measured already when the passes settled) and its data error.
    if (sys.views() > 0 && albedo_after.empty()) albedo_after = fit_detail::clamped_albedo(sys, model, threads);
    report.energy_error_after = sys.energy_error(albedo_after);
    report.weighted_error_after = weighted_error_after(sys, model, threads);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (progress) progress(1.0);
    return report;
}

}  // namespace npf
