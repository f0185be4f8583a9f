// AWLS on a block of L channels in lock-step: one SIMD lane per channel, every table stored
// cell-major with the L lanes innermost, so that a sample's D, F and G values for all lanes are
// one contiguous load. The sample geometry (cells, weights, cosines) is shared by the lanes.
#pragma once

#include "sample_set.h"

#include <npf/converter/fit/awls.h>

#include <array>
#include <cstddef>
#include <vector>

namespace npf::fit_detail {

// One block's factors, lanes innermost.
template <int L>
struct BlockFactors {
    std::vector<float> D, F, G;  // [cells][L]
    std::array<double, L> rho_d{}, rho_s{};
};

template <int L>
class BlockFit {
public:
    BlockFit(const SampleSet& samples, const AwlsOptions& options, int threads);

    // Resamples `channels` (at most L) of the source; unused lanes repeat the last channel.
    // Returns the number of non-finite values (given zero weight).
    std::size_t resample(const Brdf& source, const Channels& channels);

    // A cold start: F = G = 1, rho_s = 1, rho_d = 0 (D comes from the first update).
    BlockFactors<L> cold_start() const;
    // Every lane starts from lane `lane` of `from` (a converged neighbouring block).
    BlockFactors<L> warm_start(const BlockFactors<L>& from, int lane) const;

    // Runs AWLS to convergence; returns the iterations; `error` gets the per-lane relative
    // weighted error. `progress(iteration)` is called after each iteration.
    // `cold`: f is a cold start, whose G is replaced by Smith's masking of the first D.
    template <typename Progress>
    int run(BlockFactors<L>& f, bool cold, std::array<double, L>& error, Progress progress);

private:
    void update_d_and_diffuse(BlockFactors<L>& f);
    void update_f(BlockFactors<L>& f);
    void update_g(BlockFactors<L>& f);
    // Solves (rho_d, rho_s) jointly and returns the weighted squared error per lane.
    std::array<double, L> update_diffuse_specular(BlockFactors<L>& f, bool solve = true);
    void normalise(BlockFactors<L>& f) const;
    // G = Smith's masking of the current D, G1(w) = cos(theta) / sigma(w) with sigma the
    // projected area of D seen from w (so the table, G / cos, is 1 / sigma).
    void smith_g_from_d(BlockFactors<L>& f) const;

    // Runs body(slice) for every slice, the slices shared out over the threads.
    template <typename Body>
    void for_each_slice(Body body) const;

    // The samples are cut into a fixed number of slices (D-cell ranges of about equal sample
    // counts), each with its own partial sums, added in slice order: the fit is then the same
    // to the bit whatever the number of threads.
    static constexpr int kSlices = 16;

    const SampleSet& m_s;
    const AwlsOptions& m_o;
    std::vector<std::size_t> m_split;  // D-cell ranges of the slices
    int m_threads = 1;
    std::vector<float> m_rho, m_w;     // [samples][L]
    std::array<double, L> m_sw{}, m_swr{}, m_swrr{};  // sums of w, w rho, w rho^2
    std::vector<double> m_cell;        // per D cell: [3][L] sums of the D update
    std::vector<std::vector<float>> m_g_acc;  // per slice: [2][g_cells][L]
    std::vector<std::vector<double>> m_f_acc; // per slice: [2][f_cells][L]
    bool m_trace = false;                     // NPF_AWLS_TRACE: print the error per iteration
};

}  // namespace npf::fit_detail

#include "block_fit_impl.h"
