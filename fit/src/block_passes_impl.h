// The kernels of block_passes.h, included once per instruction set with NPF_PASSES_NS naming
// its namespace (portable, avx2). Everything here lives in that namespace or is TU-local and
// uses no out-of-line library template: code built for AVX2 must never be what the linker
// picks for a caller on a CPU without it.
//
// Inner loops run over the L lanes with no dependence between lanes, which the compiler
// vectorises (with -fno-trapping-math: a division under a condition, as in owner_shape, is
// otherwise not if-converted and its loop stays scalar).
#include "block_passes.h"

#ifndef NPF_PASSES_NS
#error "define NPF_PASSES_NS before including block_passes_impl.h"
#endif

namespace npf::fit_detail::NPF_PASSES_NS {

namespace {

inline float max0(float v) { return v > 0.f ? v : 0.f; }

// G at both directions of sample k for every lane: linear in theta between the owner cell and
// its neighbour (SampleSet), never below 0.
template <int L>
inline void interpolate_g(const float* G, const PassSamples& s, std::uint32_t k, float* gi, float* go) {
    const float* __restrict a = &G[std::size_t(s.gi[k]) * L];
    const float* __restrict a2 = &G[std::size_t(s.gi2[k]) * L];
    const float* __restrict b = &G[std::size_t(s.go[k]) * L];
    const float* __restrict b2 = &G[std::size_t(s.go2[k]) * L];
    const float ti = s.ti[k], to = s.to[k];
    for (int l = 0; l < L; ++l) {
        gi[l] = max0(a[l] + ti * (a2[l] - a[l]));
        go[l] = max0(b[l] + to * (b2[l] - b[l]));
    }
}

// The interpolated G over its owner cell's value (1 where the owner is 0).
inline float owner_shape(float interpolated, float owner) { return owner > 0.f ? interpolated / owner : 1.f; }

// What every pass reads of sample j: G at both directions (interpolate_g), 1 / (cos cos), and
// the block's data and weights.
template <int L>
struct SampleAt {
    float Gi[L], Go[L];
    float c;
    const float* __restrict rho;
    const float* __restrict w;

    SampleAt(const PassSamples& s, const float* G, std::uint32_t j)
        : c(s.inv_cc[j]), rho(&s.rho[std::size_t(j) * L]), w(&s.w[std::size_t(j) * L]) {
        interpolate_g<L>(G, s, j, Gi, Go);
    }
};

template <int L>
void d_sums(const PassSamples& s, const PassFactors& f, std::size_t k0, std::size_t k1, double* cells) {
    float rs[L];
    for (int l = 0; l < L; ++l) rs[l] = f.rho_s[l];
    for (std::size_t k = k0; k < k1; ++k) {
        float wb[L] = {}, wbb[L] = {}, wrb[L] = {};
        for (std::uint32_t r = s.cell_ring_begin[k]; r < s.cell_ring_begin[k + 1]; ++r) {
            const float* __restrict F = &f.F[std::size_t(s.ring_f[r]) * L];
            float rsf[L];
            for (int l = 0; l < L; ++l) rsf[l] = rs[l] * F[l];
            for (std::uint32_t j = s.ring_begin[r]; j < s.ring_begin[r + 1]; ++j) {
                const SampleAt<L> x(s, f.G, j);
                for (int l = 0; l < L; ++l) {
                    const float b = rsf[l] * x.Gi[l] * x.Go[l] * x.c;
                    const float w_b = x.w[l] * b;
                    wb[l] += w_b;
                    wbb[l] += w_b * b;
                    wrb[l] += w_b * x.rho[l];
                }
            }
        }
        double* cell = &cells[k * 3 * L];
        for (int l = 0; l < L; ++l) cell[l] = wb[l], cell[L + l] = wbb[l], cell[2 * L + l] = wrb[l];
    }
}

template <int L>
void f_sums(const PassSamples& s, const PassFactors& f, std::size_t k0, std::size_t k1, double* acc) {
    float rd[L], rs[L];
    for (int l = 0; l < L; ++l) rd[l] = f.rho_d[l], rs[l] = f.rho_s[l];
    for (std::size_t k = k0; k < k1; ++k) {
        float rsd[L];
        for (int l = 0; l < L; ++l) rsd[l] = rs[l] * f.D[k * L + l];
        for (std::uint32_t r = s.cell_ring_begin[k]; r < s.cell_ring_begin[k + 1]; ++r) {
            float num[L] = {}, den[L] = {};
            for (std::uint32_t j = s.ring_begin[r]; j < s.ring_begin[r + 1]; ++j) {
                const SampleAt<L> x(s, f.G, j);
                for (int l = 0; l < L; ++l) {
                    const float b = rsd[l] * x.Gi[l] * x.Go[l] * x.c;
                    const float w_b = x.w[l] * b;
                    num[l] += w_b * (x.rho[l] - rd[l]);
                    den[l] += w_b * b;
                }
            }
            double* a = &acc[std::size_t(s.ring_f[r]) * 2 * L];
            for (int l = 0; l < L; ++l) a[l] += num[l], a[L + l] += den[l];
        }
    }
}

template <int L>
void g_sums(const PassSamples& s, const PassFactors& f, std::size_t k0, std::size_t k1, float* acc) {
    float rd[L], rs[L];
    for (int l = 0; l < L; ++l) rd[l] = f.rho_d[l], rs[l] = f.rho_s[l];
    for (std::size_t k = k0; k < k1; ++k) {
        float rsd[L];
        for (int l = 0; l < L; ++l) rsd[l] = rs[l] * f.D[k * L + l];
        for (std::uint32_t r = s.cell_ring_begin[k]; r < s.cell_ring_begin[k + 1]; ++r) {
            const float* __restrict F = &f.F[std::size_t(s.ring_f[r]) * L];
            float rsdf[L];
            for (int l = 0; l < L; ++l) rsdf[l] = rsd[l] * F[l];
            for (std::uint32_t j = s.ring_begin[r]; j < s.ring_begin[r + 1]; ++j) {
                const SampleAt<L> x(s, f.G, j);
                float common[L], wa[L];
                for (int l = 0; l < L; ++l) {
                    common[l] = rsdf[l] * x.c;
                    wa[l] = x.w[l] * (x.rho[l] - rd[l]);
                }
                // Each direction updates the cell it lies in (its owner), the interpolated
                // value's shape within the cell taken from the current table.
                const float* __restrict Gi_owner = &f.G[std::size_t(s.gi[j]) * L];
                const float* __restrict Go_owner = &f.G[std::size_t(s.go[j]) * L];
                float* __restrict ai = &acc[std::size_t(s.gi[j]) * 2 * L];
                for (int l = 0; l < L; ++l) {
                    const float b = common[l] * x.Go[l] * owner_shape(x.Gi[l], Gi_owner[l]);
                    ai[l] += wa[l] * b;
                    ai[L + l] += x.w[l] * b * b;
                }
                float* __restrict ao = &acc[std::size_t(s.go[j]) * 2 * L];
                for (int l = 0; l < L; ++l) {
                    const float b = common[l] * x.Gi[l] * owner_shape(x.Go[l], Go_owner[l]);
                    ao[l] += wa[l] * b;
                    ao[L + l] += x.w[l] * b * b;
                }
            }
        }
    }
}

template <int L>
void error_sums(const PassSamples& s, const PassFactors* candidates, int count, std::size_t k0, std::size_t k1, double* out) {
    constexpr int kSums = 5;
    for (std::size_t k = k0; k < k1; ++k) {
        // Each candidate sums over the whole D cell in float and adds to double once per cell (per
        // ring, the conversions and additions were a third of this pass with 4 phi_d samples).
        // The candidates read the cell's samples one after the other, the second from cache.
        for (int c = 0; c < count; ++c) {
            const PassFactors& x = candidates[c];
            const float* __restrict Dk = &x.D[k * L];
            const float* __restrict rd = x.rho_d;
            const float* __restrict rs = x.rho_s;
            float wm[L] = {}, wmm[L] = {}, wr[L] = {}, wrm[L] = {}, wrr[L] = {};
            for (std::uint32_t r = s.cell_ring_begin[k]; r < s.cell_ring_begin[k + 1]; ++r) {
                const float* __restrict F = &x.F[std::size_t(s.ring_f[r]) * L];
                float df[L];
                for (int l = 0; l < L; ++l) df[l] = Dk[l] * F[l];
                for (std::uint32_t j = s.ring_begin[r]; j < s.ring_begin[r + 1]; ++j) {
                    const SampleAt<L> y(s, x.G, j);
                    for (int l = 0; l < L; ++l) {
                        const float m = df[l] * y.Gi[l] * y.Go[l] * y.c;
                        const float res = y.rho[l] - rd[l] - rs[l] * m;
                        const float w_m = y.w[l] * m, w_r = y.w[l] * res;
                        wm[l] += w_m;
                        wmm[l] += w_m * m;
                        wr[l] += w_r;
                        wrm[l] += w_r * m;
                        wrr[l] += w_r * res;
                    }
                }
            }
            double* o = &out[std::size_t(c) * kSums * L];
            for (int l = 0; l < L; ++l) {
                o[l] += wm[l], o[L + l] += wmm[l], o[2 * L + l] += wr[l], o[3 * L + l] += wrm[l], o[4 * L + l] += wrr[l];
            }
        }
    }
}

template <int L>
const BlockPasses<L> kPasses = {&d_sums<L>, &f_sums<L>, &g_sums<L>, &error_sums<L>};

}  // namespace

}  // namespace npf::fit_detail::NPF_PASSES_NS
