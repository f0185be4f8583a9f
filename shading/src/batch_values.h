// The table half of the batched closure's eval (npf_batch.h) as vector code: for four pairs at
// once, the cells and weights on every table (the generic axis rules of npf_equation.h), the
// basis values gathered and interpolated, and each requested value recombined per channel,
// clamped and weighted by cos(theta_light) as NpfClosure::write_values does, in the same
// operations and order as NpfModel::position and NpfModel::value: the scalar closure's results to
// the bit. AVX2 only (batch_values_avx2.cpp); the portable build shades pair by pair with the
// scalar code, which is the same arithmetic.
#pragma once

#include "batch_angles.h"

#include <npf/core/channels.h>
#include <npf/shading/npf_batch.h>
#include <npf/shading/npf_model.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace npf::batch_detail {

// The largest rank (D, G, detail) the vector path keeps per group of pairs; larger ones shade
// pair by pair (the stored models' ranks are far below: 3 for RGB, at most 16 or so spectrally).
inline constexpr int kVectorRank = 64;

inline bool vector_values_apply(const NpfModel& m) {
    return m.D.rank <= kVectorRank && m.G.rank <= kVectorRank && m.detail.rank <= kVectorRank;
}

// Cells in padded_detail_cells_of's copy of a detail layer over `grid` (below).
std::size_t padded_detail_cell_count(const DetailGrid& grid);

// Float lanes compute cell indices in float: exact below 2^24, which every table's size is far
// below; a model with a larger table takes the double path.
inline bool float_values_apply(const NpfModel& m) {
    constexpr std::size_t kExact = std::size_t(1) << 23;  // with room for the paired copies' padding
    return vector_values_apply(m) && m.D.cells < kExact && m.G.cells < kExact && padded_detail_cell_count(m.detail_grid) < kExact &&
           m.F.size() < kExact && m.D.weights.size() < kExact && m.G.weights.size() < kExact &&
           m.detail.weights.size() < kExact;
}

// Which values a block writes: every stored channel (`stored`, value k = channel k), or the
// wavelengths of `wavelengths` located on the model's grid by `locator`.
struct ValueRequestOfBlock {
    bool stored = true;
    BatchWavelengths wavelengths;
    const WavelengthLocator* locator = nullptr;
    std::size_t count = 0;  // values per pair
};

// Up to four tables of rows x cols cells each (table k at tables + k rows cols) cell by cell, four
// floats per cell (tables beyond `count` 0), padded so that the two cells an interpolation blends
// along one axis lie side by side (one load of eight floats per lane): pair_rows (a table of one
// column), one row more, a copy of the last (which the clamped and extrapolated row rules pair
// the last row with, or with the next); else each row has a column more, a copy of its first (the
// periodic column rule's neighbour of the last). Empty for more than four tables.
std::vector<float> paired_cells_of(const float* tables, int count, int rows, int cols, bool pair_rows);
// The same of a basis' ranks (empty for a rank above 4).
std::vector<float> paired_cells_of(const SpectralBasis& s, int rows, int cols, bool pair_rows);

// The detail layer's ranks (up to four tables over `grid`) cell by cell, four floats per cell,
// padded on every axis so that the corners of a trilinear lookup lie at fixed offsets from the
// first (detail_corner_offsets): theta_h and theta_d one row more, a copy of the last (which the
// clamped rule pairs the last row with, at weight 0), phi_d a column more, a copy of the first
// (the periodic neighbour of the last). Empty for more than four tables or no grid.
std::vector<float> padded_detail_cells_of(const float* tables, int count, const DetailGrid& grid);
// The same of a basis' ranks (empty for a rank above 4, or a basis not of the grid's cells).
std::vector<float> padded_detail_cells_of(const SpectralBasis& s, const DetailGrid& grid);
// The offsets (in cells) of the corner pairs q = 2a + b in that copy (a: the upper theta_h row,
// b: the upper theta_d row) from the cell at (h.i0, d.i0, p.i0); padded_detail_cell_count, above,
// is the copy's number of cells.
inline void detail_corner_offsets(const DetailGrid& grid, std::size_t offset[4]) {
    const std::size_t row = std::size_t(grid.phi_d) + 1, plane = (std::size_t(grid.theta_d) + 1) * row;
    offset[0] = 0, offset[1] = row, offset[2] = plane, offset[3] = plane + row;
}

// A basis recombined channel by channel: rank c is channel c's table (the sum of the ranks by its
// weights, in double, rounded to float), the weights the identity. Interpolation commutes with
// that sum, so the float lanes look the stored channels up in these and skip the sum per value
// (within the float budget, not to the bit). Rank 0 where there are more than 4 channels.
SpectralBasis channel_tables_of(const SpectralBasis& s, std::size_t channels);

// Each channel's coefficients in one record of eight floats: rho_d, rho_s, D's weights, G's
// weights, the detail layer's weights, then 0 (channel c at [c * 8]), so that a lane's channel
// comes with one load. Empty where they do not fit in eight.
std::vector<float> channel_records_of(const NpfModel& m);

// The paired copies of a model's bases (null where absent: values_avx2 then gathers from the
// rank-major tables, one lane and rank at a time), F in paired rows, and the channel records (null
// where absent: per-lane channels gather coefficient by coefficient).
struct CellMajorBases {
    const float* d = nullptr;
    const float* g = nullptr;
    const float* detail = nullptr;  // padded_detail_cells_of, as channel_detail
    const float* f = nullptr;  // F of up to four channels, paired rows (the stored channels' F at once)
    const float* channel_records = nullptr;
    // Paired copies of channel_tables_of's D and G and the padded copy of its detail layer (null
    // without one), for the float lanes' stored channels (stored_channels_float_avx2); d null
    // where absent.
    const float* channel_d = nullptr;
    const float* channel_g = nullptr;
    const float* channel_detail = nullptr;
};

// Pairs [0, groups * 4) of the block whose angles are `angles` and whose first pair is pair
// `first` of the batch; valid[j] is 0 for pairs outside the domain (their values are 0). Value k
// of pair i goes to values[k * n + i]. Returns the number of pairs done (a multiple of 4); the
// caller shades the rest. Only where vector_values_apply(m) and the CPU has AVX2.
std::size_t values_avx2(const NpfModel& m, const CellMajorBases& cells, const BlockAngles& angles, std::size_t count,
                        const std::uint8_t* valid, const ValueRequestOfBlock& request, std::size_t first, float* values,
                        std::size_t n);
// The same in float lanes, eight pairs per step, from float angles (BatchPrecision::Float): within
// the float budget of docs/shading.md, not to the bit. Returns a multiple of 8.
std::size_t values_float_avx2(const NpfModel& m, const CellMajorBases& cells, const BlockAnglesOf<float>& angles,
                              std::size_t count, const std::uint8_t* valid, const ValueRequestOfBlock& request,
                              std::size_t first, float* values, std::size_t n);

// The float lanes' path for stored channels (batch_stored_channels_float_avx2.cpp): where the
// request is the stored channels, at most four, and `cells` has each channel's own copies (D, G,
// the detail layer's) and F's paired rows. values_float_avx2 takes it there.
bool stored_channels_float_apply(const NpfModel& m, const CellMajorBases& cells, const ValueRequestOfBlock& request);
std::size_t stored_channels_float_avx2(const NpfModel& m, const CellMajorBases& cells, const BlockAnglesOf<float>& angles,
                                       std::size_t count, const std::uint8_t* valid, std::size_t first, float* values,
                                       std::size_t n);

}  // namespace npf::batch_detail
