// The angle kernels of the batched closure (npf_batch.h): pair_angles and half_vector_angles
// over a block of pairs, written to structure-of-arrays so that the loop runs as vector code.
// Two implementations: the portable one (the scalar code per pair) and AVX2 (four pairs per
// step, without FMA), both giving the scalar closure's results to the bit.
#pragma once

#include <npf/shading/npf_pair_angles.h>

#include <cstddef>
#include <cstdint>

namespace npf::batch_detail {

inline constexpr std::size_t kBlock = 64;  // pairs per block: the angles stay in L1

// S: double (the double path), or float (BatchPrecision::Float's lanes).
template <class S>
struct BlockAnglesOf {
    S cos_i[kBlock], cos_o[kBlock], inv_cos_product[kBlock];
    S theta_h[kBlock], u_h[kBlock], phi_h[kBlock], cos_d[kBlock], theta_d[kBlock];
    S theta_gi[kBlock], phi_gi[kBlock], theta_go[kBlock], phi_go[kBlock], phi_d[kBlock];

    PairAnglesOf<S> at(std::size_t i) const {
        return {cos_i[i], cos_o[i], inv_cos_product[i], theta_h[i], u_h[i], phi_h[i], cos_d[i],
                theta_d[i], theta_gi[i], phi_gi[i], theta_go[i], phi_go[i], phi_d[i]};
    }
};
using BlockAngles = BlockAnglesOf<double>;

// Writes pair angles of any number type at position i of the block: store(pointer, value)
// puts one value (double) or a vector's there. The one list of the fields.
template <class Out, class T, class Store>
void store_angles(Out& out, std::size_t i, const PairAnglesOf<T>& a, Store store) {
    store(out.cos_i + i, a.cos_i);
    store(out.cos_o + i, a.cos_o);
    store(out.inv_cos_product + i, a.inv_cos_product);
    store(out.theta_h + i, a.theta_h);
    store(out.u_h + i, a.u_h);
    store(out.phi_h + i, a.phi_h);
    store(out.cos_d + i, a.cos_d);
    store(out.theta_d + i, a.theta_d);
    store(out.theta_gi + i, a.theta_gi);
    store(out.phi_gi + i, a.phi_gi);
    store(out.theta_go + i, a.theta_go);
    store(out.phi_go + i, a.phi_go);
    store(out.phi_d + i, a.phi_d);
}

struct BlockHalfVectors {
    double theta_h[kBlock], u_h[kBlock], phi_h[kBlock], cos_d[kBlock];
};

// Pairs [first, first + n) of a block (first + n <= kBlock): view x, y, z then light x, y, z,
// each array indexed from the block's start. Pairs at or below the horizon get meaningless values
// (the caller skips them).
void angles_portable(std::size_t n, const float* const view[3], const float* const light[3], AngleNeeds needs,
                     BlockAngles& out, std::size_t first = 0);
void half_vectors_portable(std::size_t n, const float* const view[3], const float* const light[3], bool d_azimuth,
                           BlockHalfVectors& out, std::size_t first = 0);
void angles_avx2(std::size_t n, const float* const view[3], const float* const light[3], AngleNeeds needs, BlockAngles& out);
void half_vectors_avx2(std::size_t n, const float* const view[3], const float* const light[3], bool d_azimuth,
                       BlockHalfVectors& out);
// pair_in_domain (npf_pair_angles.h) of pairs [0, n) rounded down to a multiple of 8, eight at a
// time: valid[j] 1 or 0. Returns how many (0 without AVX2 in the build); the caller does the rest.
std::size_t domains_avx2(std::size_t n, const float* const view[3], const float* const light[3], std::uint8_t* valid);
// The same angles in float, eight pairs per step (BatchPrecision::Float): pairs [0, n) rounded
// down to a multiple of 8; returns how many (0 without AVX2 in the build).
std::size_t angles_float_avx2(std::size_t n, const float* const view[3], const float* const light[3], AngleNeeds needs,
                              BlockAnglesOf<float>& out);

}  // namespace npf::batch_detail
