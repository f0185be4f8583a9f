// The batched closure's pdf for AVX2 (batch_pdf.h). Compiled with -mavx2 and without FMA
// (CMakeLists.txt), called only where the CPU has AVX2 (npf_batch.cpp). Each step is the scalar
// code's IEEE operation on four lanes, so the pdfs equal NpfClosure::pdf_at's to the bit
// (shading/tests/test_batch_closure.cpp); the float lanes' version takes the same steps in float.
#include "batch_pdf.h"

#if defined(__AVX2__)
#include "simd_double4.h"
#include "simd_float8.h"

namespace npf::batch_detail {

namespace {

using simd::Double4;
using simd::Float8;
using simd::Mask4;

Mask4 operator&&(Mask4 a, Mask4 b) { return {_mm256_and_pd(a.m, b.m)}; }

// std::min(int(x), last) for x >= 0 (as the scalar code's truncating conversion), as int32; held
// in [0, last] for any x, so that a pair outside the domain (whose angles mean nothing) reads in
// bounds too.
__m128i cell_of(Double4 x, int last) {
    return _mm_max_epi32(_mm_min_epi32(_mm256_cvttpd_epi32(x.v), _mm_set1_epi32(last)), _mm_setzero_si128());
}

}  // namespace

std::size_t pdfs_avx2(const HalfVectorSampler& sampler, double diffuse_probability, std::size_t n, const double* theta_h,
                      const double* u_h, const double* phi_h, const double* cos_d, const double* cos_light,
                      const std::uint8_t* valid, float* pdf) {
    if (sampler.empty() || !(diffuse_probability < 1.0)) return 0;
    const std::vector<AliasTable::Bin>& bins = sampler.cells().bins();
    const double* inv_solid_angle = sampler.inv_solid_angle().data();
    const int rows = sampler.theta_cells(), columns = sampler.phi_cells();
    const Double4 pd(diffuse_probability), spec_share(1.0 - diffuse_probability);
    const std::size_t groups = n - n % 4;
    for (std::size_t i = 0; i < groups; i += 4) {
        const Double4 theta = simd::load4(theta_h + i), u = simd::load4(u_h + i), phi = simd::load4(phi_h + i);
        const Double4 cd = simd::load4(cos_d + i);
        // HalfVectorSampler::pdf(theta, u, phi): its cell's pmf over its solid angle; 0 outside
        // (those lanes read some cell, then drop it).
        const Mask4 inside = theta < Double4(kHalfPiD) && Mask4{_mm256_cmp_pd(phi.v, _mm256_setzero_pd(), _CMP_GE_OQ)};
        alignas(16) std::int32_t k[4], j[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(k), cell_of(u * Double4(double(rows)), rows - 1));
        _mm_store_si128(reinterpret_cast<__m128i*>(j), cell_of(phi / Double4(kTwoPiD) * Double4(double(columns)), columns - 1));
        double pmf[4], inv[4];
        for (int l = 0; l < 4; ++l) {
            pmf[l] = double(bins[std::size_t(k[l]) * std::size_t(columns) + std::size_t(j[l])].pmf);
            inv[l] = inv_solid_angle[k[l]];
        }
        const Double4 sampler_pdf = simd::select(inside, simd::load4(pmf) * simd::load4(inv), Double4(0.0));
        // pdf_at: the mixture with the cosine strategy, then finite_float.
        Double4 p = pd * simd::load4(cos_light + i) * Double4(1.0 / kPiD);
        p = simd::select(cd > Double4(0.0), p + spec_share * sampler_pdf / (Double4(4.0) * cd), p);
        p = simd::finite_float_of(p);
        if (valid) p = simd::select(simd::nonzero_bytes4(valid + i), p, Double4(0.0));
        _mm_storeu_ps(pdf + i, _mm256_cvtpd_ps(p.v));
    }
    return groups;
}

std::size_t pdfs_float_avx2(const HalfVectorSampler& sampler, double diffuse_probability, std::size_t n, const float* theta_h,
                            const float* u_h, const float* phi_h, const float* cos_d, const float* cos_light,
                            const std::uint8_t* valid, float* pdf) {
    if (sampler.empty() || !(diffuse_probability < 1.0)) return 0;
    const float* density = sampler.cell_density().data();
    const int rows = sampler.theta_cells(), columns = sampler.phi_cells();
    const Float8 pd(diffuse_probability), spec_share(1.0 - diffuse_probability);
    const __m256i last_row = _mm256_set1_epi32(rows - 1), last_column = _mm256_set1_epi32(columns - 1), zero = _mm256_setzero_si256();
    const std::size_t groups = n - n % 8;
    for (std::size_t i = 0; i < groups; i += 8) {
        const Float8 theta = simd::load8(theta_h + i), u = simd::load8(u_h + i), phi = simd::load8(phi_h + i);
        const Float8 cd = simd::load8(cos_d + i);
        const __m256 inside = _mm256_and_ps((theta < Float8(kHalfPiD)).m, _mm256_cmp_ps(phi.v, _mm256_setzero_ps(), _CMP_GE_OQ));
        const __m256i k_cell = _mm256_max_epi32(_mm256_min_epi32(_mm256_cvttps_epi32((u * Float8(double(rows))).v), last_row), zero);
        const __m256i j_cell = _mm256_max_epi32(
            _mm256_min_epi32(_mm256_cvttps_epi32((phi / Float8(kTwoPiD) * Float8(double(columns))).v), last_column), zero);
        const __m256i cell = columns == 1 ? k_cell : _mm256_add_epi32(_mm256_mullo_epi32(k_cell, _mm256_set1_epi32(columns)), j_cell);
        const Float8 sampler_pdf = Float8(_mm256_and_ps(inside, simd::gather(density, cell).v));
        Float8 p = pd * simd::load8(cos_light + i) * Float8(1.0 / kPiD);
        p = simd::select(cd > Float8(0.0), p + spec_share * sampler_pdf / (Float8(4.0) * cd), p);
        p = simd::finite_float_of(p);
        if (valid) p = simd::select(simd::nonzero_bytes8(valid + i), p, Float8(0.0));
        simd::store8(pdf + i, p);
    }
    return groups;
}

}  // namespace npf::batch_detail
#else
namespace npf::batch_detail {
std::size_t pdfs_avx2(const HalfVectorSampler&, double, std::size_t, const double*, const double*, const double*,
                      const double*, const double*, const std::uint8_t*, float*) {
    return 0;
}
std::size_t pdfs_float_avx2(const HalfVectorSampler&, double, std::size_t, const float*, const float*, const float*,
                            const float*, const float*, const std::uint8_t*, float*) {
    return 0;
}
}  // namespace npf::batch_detail
#endif
