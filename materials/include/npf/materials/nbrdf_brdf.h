// Neural BRDF networks (Sztrajman, Rainer, Ritschel, Weyrich, "Neural BRDF Representation and
// Importance Sampling", CGF 40(6), 2021), the paper's baseline: Keras HDF5 weight files (`.h5`).
//
// The network is a multilayer perceptron 6 -> n1 (ReLU) -> n2 (ReLU) -> 3 (linear), followed by
// exp(x) - 1; the published networks have n1 = n2 = 21 (675 weights). Its input is the
// Rusinkiewicz half vector, with phi_h set to 0 because the networks are isotropic, and the
// difference vector, as Cartesian coordinates (hx, hy, hz, dx, dy, dz); its outputs are f_r in
// 1/sr for linear R, G, B. Weights are read from `dense_k/dense_k/kernel:0` (inputs x units) and
// `dense_k/dense_k/bias:0`, k = 1, 2, 3; layer k computes y = x W + b.
//
// Direction convention (checked against the RGL files the networks were trained from, see
// docs/measured-readers.md): the difference vector is formed from `wo`, the direction the
// project does not condition on (the light side in a renderer), as the authors' Mitsuba plugin
// does with Mitsuba's bRec.wo.
#pragma once

#include <npf/materials/isotropic_rgb_brdf.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace npf {

class NbrdfBrdf final : public IsotropicRgbBrdf {
public:
    // Widest hidden layer accepted: evaluation keeps the activations on the stack.
    static constexpr int kMaxHiddenUnits = 256;
    static constexpr int kInputs = 6;
    static constexpr int kOutputs = 3;

    // Throws npf::Error naming the file and the problem (missing, not HDF5, damaged, a missing
    // dataset, shapes that do not chain 6 -> n1 -> n2 -> 3, non-finite weights). A material is
    // read from its own file alone: external storage, external, soft and user-defined links,
    // virtual datasets, objects with several links and filters HDF5 would load from plugins are
    // refused, and the root's attributes (Keras's version) are not read. info().value_bound is an
    // upper bound of f_r cos(theta_i) cos(theta_o) over all pairs, by interval arithmetic through
    // the network; a network above kMaxMaterialValue, or whose float evaluation could overflow,
    // is refused.
    static std::unique_ptr<NbrdfBrdf> load(const std::string& path);

    // Format sniffing: the HDF5 signature at the start of the file.
    static bool has_hdf5_signature(const std::uint8_t* head, std::size_t head_size);

    // pdf and sample: cosine-weighted (the network has no inverse).
    void eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out) const override;

    // The network's six inputs for one direction pair (both above the horizon).
    static void network_input(const Vec3& wi, const Vec3& wo, float input[kInputs]);
    // The network's output, f_r for R, G, B, unclamped (exp(x) - 1 may dip below 0).
    void forward(const float input[kInputs], float rgb[kOutputs]) const;

    int hidden1_units() const { return m_layers[0].units; }
    int hidden2_units() const { return m_layers[1].units; }

private:
    NbrdfBrdf() = default;

    struct DenseLayer {
        int inputs = 0, units = 0;
        int stride = 0;             // units rounded up to the evaluation's vector width
        std::vector<float> kernel;  // inputs x stride, row-major: kernel[i * stride + j]; zero padding
        std::vector<float> bias;    // stride, zero padding
    };

    DenseLayer m_layers[3];
};

}  // namespace npf
