// The fitter's samples: everything about a grid sample that does not depend on the channel,
// computed once per fit and shared by every channel.
//
// Samples are ordered by D cell, then by theta_d ring, then by phi_d, so that the passes of
// the fit read D once per cell and F once per ring, and two threads can take disjoint ranges
// of D cells.
#pragma once

#include <npf/fit/awls.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace npf::fit_detail {

struct SampleSet {
    std::size_t d_cells = 0, f_cells = 0, g_cells = 0;
    std::vector<std::uint32_t> cell_ring_begin;  // [d_cells + 1]: rings of each D cell
    std::vector<std::uint32_t> ring_begin;       // [rings + 1]: samples of each ring
    std::vector<std::uint16_t> ring_f;           // [rings]: the ring's F cell (theta_d)
    // G is linear in theta between cell centres, in the fit as in evaluation: a direction's
    // value is (1 - t) G[owner] + t G[neighbour], the owner the cell it lies in (the one its
    // sample updates), the neighbour the next cell in theta towards it (t in [0, 1/2]); beyond
    // the last centre the line through the last two cells continues to the horizon (t < 0),
    // where G may fall to zero as Smith's masking does; below the first centre G is flat.
    std::vector<std::uint32_t> gi, go;           // [samples]: owner G cells of wi and wo
    std::vector<std::uint32_t> gi2, go2;         // [samples]: their neighbours in theta
    std::vector<float> ti, to;                   // [samples]: the neighbours' weights
    std::vector<float> inv_cc;                   // [samples]: 1 / (cos theta_i cos theta_o)
    std::vector<float> geometry;                 // [samples]: w_V w_I
    std::vector<float> directions;               // [samples][6]: wi then wo, for resampling

    std::size_t size() const { return gi.size(); }
    std::size_t rings() const { return ring_f.size(); }
};

// Throws npf::Error when the grid yields no sample above the horizon.
SampleSet make_sample_set(const AwlsOptions& options, int threads);

// Splits the D cells into `parts` contiguous ranges with about equal sample counts:
// returns parts + 1 cell boundaries.
std::vector<std::size_t> balanced_cell_split(const SampleSet& samples, int parts);

}  // namespace npf::fit_detail
