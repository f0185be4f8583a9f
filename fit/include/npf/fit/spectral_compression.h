// Spectral compression of the fitted factors (paper sec. 3.4, Eqs. 11 and 12): D and G look
// alike at every wavelength, so each is stored as a few basis tables shared by all channels.
//
// The tables of one factor form a cells x channels matrix A (column c = channel c's table). Its
// SVD A = U S V^T, truncated to rank r, gives the basis u_k (columns of U) and the weights
// w[c][k] = sigma_k v_k(c), so that table_c ~ sum_{k<r} w[c][k] u_k: the best rank-r
// approximation in the least-squares sense. The data are not centred (the mean table is a
// basis vector like any other), so the tables' scale is kept exactly.
//
// Rank choice: the cumulative contribution ratio of rank r is
//   sum_{k<=r} sigma_k^2 / sum_k sigma_k^2,
// the share of the tables' total squared magnitude the first r components keep (PCA's
// eigenvalue share). The chosen rank is the smallest whose ratio reaches the requested one; a
// ratio of 1 keeps every component (lossless to float precision: rank min(cells, channels)).
// A positive explicit rank overrides the ratio (clamped to min(cells, channels)).
//
// Per channel (CompressionOptions::per_channel, the default but for the paper preset): the ratio
// must hold for every channel's own table, sum_{k<r} w[c][k]^2 >= ratio |table_c|^2, not only for
// the total. The total is ruled by the bright channels; a colour that shifts with angle (a paint
// whose highlight is gold and whose edge is violet) sits in a small second component that the
// total ratio drops, and the wavelengths that need it lose a third of their light.
//
// Each basis vector's largest-magnitude entry is made positive (its weights flip with it), so
// the output is deterministic.
#pragma once

#include <npf/fit/npf_factors.h>
#include <npf/shading/npf_model.h>

namespace npf {

struct CompressionOptions {
    double d_ratio = 1.0, g_ratio = 1.0;  // in (0, 1]; 1 keeps all components
    int d_rank = 0, g_rank = 0;           // > 0 fixes the rank; 0 chooses it by ratio
    bool per_channel = true;              // the ratio holds for every channel (above), not only the total
};

// The model with D and G compressed and rho_d, rho_s, F copied; metadata empty. Throws
// npf::Error for options out of range or factors whose table sizes disagree.
NpfModel compress_factors(const NpfFactors& factors, const CompressionOptions& options);

// The same compression for any set of tables: `tables` holds `channels` tables of `cells` values,
// channel after channel; the rank by `ratio`, or `fixed_rank` when positive (the detail layer's).
SpectralBasis compress_tables(const std::vector<float>& tables, std::size_t channels, std::size_t cells, double ratio,
                              int fixed_rank, bool per_channel = false);

// The smallest rank whose cumulative contribution ratio reaches `ratio` (see above); all of
// them for ratio >= 1, 1 when every singular value is 0.
int rank_for_ratio(const std::vector<double>& singular_values, double ratio);

}  // namespace npf
