// AWLS on a block of L channels in lock-step: one SIMD lane per channel, every table stored
// cell-major with the L lanes innermost, so that a sample's D, F and G values for all lanes are
// one contiguous load. The sample geometry (cells, weights, cosines) is shared by the lanes.
#pragma once

#include "anderson.h"
#include "block_factors.h"
#include "block_passes.h"
#include "sample_set.h"

#include <npf/fit/awls.h>

#include <array>
#include <cstddef>
#include <vector>

namespace npf::fit_detail {

template <int L>
class BlockFit {
public:
    BlockFit(const SampleSet& samples, const AwlsOptions& options, int threads);

    // Evaluates the source at every sample for the channels of several consecutive blocks in
    // one pass: one eval_cos per direction pair for all of them, so that a reader whose cost is
    // per pair (the RGL reader's VNDF inversion and interpolation weights; with more than 8
    // channels it interpolates every stored channel whatever the query) pays it once, not once
    // per block. `values[b]` gets block b's values, [samples][L], unused lanes repeating the
    // block's last channel (buffers already of that size are reused as they are); a channel's
    // values do not depend on which others are asked for.
    static void evaluate(const SampleSet& samples, const Brdf& source, const std::vector<Channels>& blocks, int threads,
                         std::vector<std::vector<float>>& values);
    // Takes one block's values (from evaluate; `channels` of its lanes are real) as the data of
    // the fit: weights, sums. `values` gets the previous block's buffer back (empty the first
    // time), for evaluate to refill: fresh 0.56 GB buffers per block were zero-filled and
    // page-faulted in, 5 % of a 195-wavelength conversion. Returns the number of non-finite
    // values (given zero weight).
    std::size_t load(std::vector<float>& values, std::size_t channels);

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
    // run's steps.
    struct Acceleration {
        Anderson<L> anderson;
        BlockFactors<L> before, mix;  // a sweep's start; the candidate
        std::array<double, L> step;   // the line search's extrapolation step per lane
    };
    void pin_gauge(const BlockFactors<L>& f, bool cold);
    void sweep(BlockFactors<L>& f, bool smith);
    std::array<bool, L> propose(Acceleration& a, const BlockFactors<L>& f, bool smith, int it) const;
    std::array<double, L> keep_better(BlockFactors<L>& f, Acceleration& a, const std::array<bool, L>& mixed,
                                      std::array<char, L>& kept);
    void trace(int it, const std::array<double, L>& e, const std::array<char, L>& kept) const;
    bool converged(const std::vector<std::array<double, L>>& history) const;

    void update_d_and_diffuse(BlockFactors<L>& f);
    void update_f(BlockFactors<L>& f);
    void update_g(BlockFactors<L>& f);
    // Solves (rho_d, rho_s) jointly and returns the weighted squared error per lane.
    std::array<double, L> update_diffuse_specular(BlockFactors<L>& f);
    // The same for up to kMaxCandidates sets of factors in one pass over the samples.
    static constexpr int kMaxCandidates = 2;
    void update_diffuse_specular(BlockFactors<L>* const* candidates, int count, std::array<double, L>* errors);
    void normalise(BlockFactors<L>& f) const;
    // G = Smith's masking of the current D, G1(w) = cos(theta) / sigma(w) with sigma the
    // projected area of D seen from w (so the table, G / cos, is 1 / sigma).
    void smith_g_from_d(BlockFactors<L>& f) const;

    // Runs `pass` (one of m_passes') on f over every slice into the slice's accumulator in
    // `acc`, first zeroed to `size` values.
    template <typename T, typename Pass>
    void run_pass(Pass pass, const BlockFactors<L>& f, std::size_t size, std::vector<std::vector<T>>& acc);
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
    const BlockPasses<L>& m_passes;    // the sums over the samples, for this CPU
    std::vector<float> m_rho, m_w;     // [samples][L]
    std::array<double, L> m_sw{}, m_swr{}, m_swrr{};  // sums of w, w rho, w rho^2
    std::vector<double> m_cell;        // per D cell: [3][L] sums of the D update
    std::vector<std::vector<float>> m_g_acc;  // per slice: [2][g_cells][L]
    std::vector<float> m_g_ref;               // G that the fit's gauge is pinned to
    std::vector<float> m_g_anchor;            // the pin of every warm block: the first warm start's G
    std::vector<std::vector<double>> m_f_acc; // per slice: [2][f_cells][L]
    bool m_trace = false;                     // NPF_AWLS_TRACE: print the error per sweep and lane
};

}  // namespace npf::fit_detail

#include "block_fit_impl.h"
