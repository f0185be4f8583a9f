// The fitter's passes over the samples (the sums behind each AWLS update), as plain functions on
// raw arrays, built once per instruction set (block_passes_portable.cpp, block_passes_avx2.cpp)
// and chosen at run time by npf::simd_isa(). They give the same bits on either: the same
// arithmetic per lane, sums in the same order, no fused multiply-add (tested).
//
// Each pass covers the D cells [k0, k1) of one slice of BlockFit; lanes are innermost
// everywhere (BlockFit's layout, block_fit.h).
#pragma once

#include "sample_set.h"

#include <cstddef>
#include <cstdint>

namespace npf::fit_detail {

// A block's data and the sample geometry it is fitted on.
struct PassSamples {
    const std::uint32_t* cell_ring_begin;
    const std::uint32_t* ring_begin;
    const std::uint16_t* ring_f;
    const std::uint32_t *gi, *go, *gi2, *go2;
    const float *ti, *to, *inv_cc;
    const float* rho;  // [samples][L]
    const float* w;    // [samples][L]
};

// One set of factors: the tables [cells][L] and rho_d, rho_s [L] (as floats, as the passes use them).
struct PassFactors {
    const float *D, *F, *G;
    const float *rho_d, *rho_s;
};

template <int L>
struct BlockPasses {
    // Per D cell: sums of w b, w b^2 and w rho b with b = rho_s F G G / cc, written to
    // cells[k][3][L] (the joint D and rho_d update).
    void (*d_sums)(const PassSamples&, const PassFactors&, std::size_t k0, std::size_t k1, double* cells);
    // Adds, per F cell, w b (rho - rho_d) and w b^2 with b = rho_s D G G / cc to acc[f][2][L].
    void (*f_sums)(const PassSamples&, const PassFactors&, std::size_t k0, std::size_t k1, double* acc);
    // Adds, per G cell, each sample's two one-sided updates (the cell of wi with wo's G held and
    // the reverse) to acc[g][2][L].
    void (*g_sums)(const PassSamples&, const PassFactors&, std::size_t k0, std::size_t k1, float* acc);
    // Adds, for each of `count` candidate factor sets, the sums w m, w m^2, w r, w r m and w r^2
    // (m = D F G G / cc, r = rho - rho_d - rho_s m) to out[c][5][L].
    void (*error_sums)(const PassSamples&, const PassFactors* candidates, int count, std::size_t k0, std::size_t k1,
                       double* out);
};

// The passes for the current npf::simd_isa().
template <int L>
const BlockPasses<L>& block_passes();

namespace portable {
template <int L>
const BlockPasses<L>& passes();
}
namespace avx2 {
// Null where the build has no AVX2 kernels (not GCC or Clang on x86).
template <int L>
const BlockPasses<L>* passes();
}

inline PassSamples pass_samples(const SampleSet& s, const float* rho, const float* w) {
    return {s.cell_ring_begin.data(), s.ring_begin.data(), s.ring_f.data(), s.gi.data(), s.go.data(), s.gi2.data(),
            s.go2.data(), s.ti.data(), s.to.data(), s.inv_cc.data(), rho, w};
}

}  // namespace npf::fit_detail
