// Neural BRDF reader and evaluator. The weights are read once with the HDF5 C API
// (nbrdf/hdf5_weights_file.cpp) and bounded (nbrdf/network_bound.cpp); evaluation is a float
// forward pass over arrays on the stack, so eval never touches HDF5 and never allocates.
#include <npf/materials/nbrdf_brdf.h>

#include "nbrdf/hdf5_weights_file.h"
#include "nbrdf/network_bound.h"

#include <npf/core/number_text.h>
#include <npf/core/error.h>
#include <npf/core/input_file.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

namespace npf {

using nbrdf::kLayerCount;

namespace {

// The HDF5 format signature (at offset 0 unless the file has a user block).
constexpr std::uint8_t kHdf5Signature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

std::string dataset_path(int layer, const char* weight) {
    const std::string name = "dense_" + std::to_string(layer);
    return name + "/" + name + "/" + weight + ":0";
}


// One dense layer's weights, read and checked: a kernel of `inputs` x units (3 for the last
// layer), a bias of units, all finite.
struct LayerWeights {
    std::vector<float> kernel, bias;  // inputs x units, row-major; units
    int units = 0;
};

LayerWeights read_layer(const nbrdf::Hdf5WeightsFile& file, const std::string& path, int k, int inputs) {
    constexpr int kOutputs = NbrdfBrdf::kOutputs, kMaxHiddenUnits = NbrdfBrdf::kMaxHiddenUnits;
    const bool last = k + 1 == kLayerCount;
    const std::string kernel_name = dataset_path(k + 1, "kernel");
    const std::string bias_name = dataset_path(k + 1, "bias");
    std::vector<hsize_t> kernel_dims, bias_dims;
    LayerWeights w;
    w.kernel = file.read_floats(kernel_name, kernel_dims);
    w.bias = file.read_floats(bias_name, bias_dims);

    const std::string wanted = std::to_string(inputs) + " x " + (last ? std::to_string(kOutputs) : std::string("n"));
    const bool kernel_ok = kernel_dims.size() == 2 && kernel_dims[0] == hsize_t(inputs) &&
                           (last ? kernel_dims[1] == hsize_t(kOutputs)
                                 : kernel_dims[1] >= 1 && kernel_dims[1] <= hsize_t(kMaxHiddenUnits));
    if (!kernel_ok)
        throw Error(path, kernel_name + " has shape " + nbrdf::shape_text(kernel_dims) + ", expected " + wanted +
                              (last ? "" : " with 1 <= n <= " + std::to_string(kMaxHiddenUnits)) +
                              " (network 6 -> n1 -> n2 -> 3)");
    w.units = static_cast<int>(kernel_dims[1]);
    if (bias_dims.size() != 1 || bias_dims[0] != hsize_t(w.units))
        throw Error(path, bias_name + " has shape " + nbrdf::shape_text(bias_dims) + ", expected " +
                              std::to_string(w.units) + " (the kernel's units)");
    for (const std::vector<float>* values : {&w.kernel, &w.bias}) {
        const auto bad = std::find_if(values->begin(), values->end(), [](float v) { return !std::isfinite(v); });
        if (bad != values->end())
            throw Error(path, "non-finite weight in " + (values == &w.kernel ? kernel_name : bias_name) + " at index " +
                                  std::to_string(bad - values->begin()));
    }
    return w;
}

// Layer widths are padded with zero weights to a multiple of this many lanes, so that the inner
// loops have trip counts the compiler vectorises without remainder loops.
constexpr int kLanes = 8;

int padded(int units) { return (units + kLanes - 1) / kLanes * kLanes; }

// y = relu?(x W + b) for one dense layer of `Stride` (padded) units; W row-major, inputs x
// Stride, padding columns zero. With the width known at compile time all the sums stay in
// registers and the inputs' additions overlap; loops over a run-time width were 1.5 to 2x slower.
template <int Stride>
void dense_fixed(const float* x, int inputs, const float* kernel, const float* bias, bool relu,
                 float* y) {
    float sum[Stride];
    for (int j = 0; j < Stride; ++j) sum[j] = bias[j];
    for (int i = 0; i < inputs; ++i) {
        const float xi = x[i];
        const float* row = kernel + static_cast<std::size_t>(i) * Stride;
        for (int j = 0; j < Stride; ++j) sum[j] += xi * row[j];
    }
    for (int j = 0; j < Stride; ++j) y[j] = relu ? std::max(sum[j], 0.f) : sum[j];
}

// Any width: kLanes outputs at a time.
void dense_blocks(const float* x, int inputs, const float* kernel, const float* bias, int stride,
                  bool relu, float* y) {
    for (int j0 = 0; j0 < stride; j0 += kLanes) {
        float sum[kLanes];
        for (int j = 0; j < kLanes; ++j) sum[j] = bias[j0 + j];
        for (int i = 0; i < inputs; ++i) {
            const float xi = x[i];
            const float* row = kernel + static_cast<std::size_t>(i) * stride + j0;
            for (int j = 0; j < kLanes; ++j) sum[j] += xi * row[j];
        }
        for (int j = 0; j < kLanes; ++j) y[j0 + j] = relu ? std::max(sum[j], 0.f) : sum[j];
    }
}

void dense(const float* x, int inputs, const float* kernel, const float* bias, int stride,
           bool relu, float* y) {
    switch (stride) {
        case 8: return dense_fixed<8>(x, inputs, kernel, bias, relu, y);    // the RGB output layer
        case 24: return dense_fixed<24>(x, inputs, kernel, bias, relu, y);  // the published 21 units
        case 32: return dense_fixed<32>(x, inputs, kernel, bias, relu, y);
        default: return dense_blocks(x, inputs, kernel, bias, stride, relu, y);
    }
}

}  // namespace

// ---- Loading -----------------------------------------------------------------------------

bool NbrdfBrdf::has_hdf5_signature(const std::uint8_t* head, std::size_t head_size) {
    return head != nullptr && head_size >= sizeof(kHdf5Signature) &&
           std::memcmp(head, kHdf5Signature, sizeof(kHdf5Signature)) == 0;
}

std::unique_ptr<NbrdfBrdf> NbrdfBrdf::load(const std::string& path) {
    const std::uint64_t file_size = require_regular_file(path, "a Neural BRDF file");
    if (file_size == 0) throw Error(path, "file is empty");

    // Held to the end: one HDF5 reader at a time, its error printing off.
    const nbrdf::Hdf5WeightsFile file(path, file_size);

    auto brdf = std::unique_ptr<NbrdfBrdf>(new NbrdfBrdf());
    int inputs = kInputs;
    for (int k = 0; k < kLayerCount; ++k) {
        const LayerWeights weights = read_layer(file, path, k, inputs);
        const int units = weights.units;
        DenseLayer& layer = brdf->m_layers[k];
        layer.inputs = inputs;
        layer.units = units;
        layer.stride = padded(units);
        layer.kernel.assign(static_cast<std::size_t>(inputs) * layer.stride, 0.f);
        for (int i = 0; i < inputs; ++i)
            std::copy_n(weights.kernel.begin() + static_cast<std::ptrdiff_t>(i) * units, units,
                        layer.kernel.begin() + static_cast<std::ptrdiff_t>(i) * layer.stride);
        layer.bias.assign(static_cast<std::size_t>(layer.stride), 0.f);
        std::copy(weights.bias.begin(), weights.bias.end(), layer.bias.begin());
        inputs = units;
    }
    // A deeper network would be evaluated wrongly, not approximately: refuse it.
    const std::string extra = "dense_" + std::to_string(kLayerCount + 1);
    if (file.exists(extra))
        throw Error(path, "has a layer " + extra + ": expected exactly 3 dense layers (6 -> n1 -> n2 -> 3)");
    // The root's keras_version and backend attributes are not read: Keras writes them as
    // variable-length strings, which HDF5 copies into a buffer of the length the file claims
    // (a 4-byte edit made `npf info` take 4 GB and 16 s; a shorter claim overflows the buffer).

    nbrdf::LayerView layers[kLayerCount];
    for (int k = 0; k < kLayerCount; ++k) {
        const DenseLayer& l = brdf->m_layers[k];
        layers[k] = {l.kernel.data(), l.bias.data(), l.inputs, l.units, l.stride};
    }
    const nbrdf::NetworkBound bound = nbrdf::bound_network(layers);
    check_value_bound(path, bound.value,
                      "exp(output) - 1 by interval arithmetic over " + std::to_string(bound.boxes) +
                          " boxes of direction pairs, x cos(theta_i) cos(theta_o)");
    if (!(bound.activation <= nbrdf::kMaxActivation))
        throw Error(path, "a unit of the network can reach " + number_text(bound.activation) +
                              ", beyond the 1e30 within which its float evaluation cannot overflow: refused as corrupt");
    if (!(bound.output <= nbrdf::kMaxOutput))
        throw Error(path, "the network's output x can reach " + number_text(bound.output) +
                              ", and exp(x) - 1 overflows single precision above 88: refused as corrupt");

    const int n1 = brdf->m_layers[0].units, n2 = brdf->m_layers[1].units;
    const int weights = (kInputs + 1) * n1 + (n1 + 1) * n2 + (n2 + 1) * kOutputs;
    brdf->describe_rgb_file("nbrdf", path, file_size);
    BrdfInfo& info = brdf->m_info;
    info.value_bound = bound.value;
    info.details = {
        {"network", "6 -> " + std::to_string(n1) + " (ReLU) -> " + std::to_string(n2) +
                        " (ReLU) -> 3 (linear), then exp(x) - 1"},
        {"weights", std::to_string(weights)},
        {"input", "half vector (phi_h = 0) and difference vector of wo"},
        {"output", "f_r in 1/sr, R G B"},
        {"sampling", "cosine-weighted"},
    };
    return brdf;
}

// ---- Evaluation --------------------------------------------------------------------------

void NbrdfBrdf::network_input(const Vec3& wi, const Vec3& wo, float input[kInputs]) {
    const Vec3 h = normalize(wi + wo);
    const float sin_h = std::sqrt(h.x * h.x + h.y * h.y);
    const float cos_h = h.z;
    // Rotating by -phi_h about the normal, then by -theta_h about the bitangent, brings the half
    // vector to the normal; the difference vector is wo in that frame. At the normal phi_h is
    // undefined and taken as 0, as atan2(0, 0) gives in the authors' code.
    const float cos_phi = sin_h > 0.f ? h.x / sin_h : 1.f;
    const float sin_phi = sin_h > 0.f ? h.y / sin_h : 0.f;
    const Vec3 v = normalize(wo);
    const float x1 = v.x * cos_phi + v.y * sin_phi;
    const float y1 = -v.x * sin_phi + v.y * cos_phi;
    const Vec3 d = normalize(Vec3(x1 * cos_h - v.z * sin_h, y1, x1 * sin_h + v.z * cos_h));
    input[0] = sin_h;
    input[1] = 0.f;
    input[2] = cos_h;
    input[3] = d.x;
    input[4] = d.y;
    input[5] = d.z;
}

void NbrdfBrdf::forward(const float input[kInputs], float rgb[kOutputs]) const {
    float hidden1[kMaxHiddenUnits], hidden2[kMaxHiddenUnits], linear[kLanes];
    const DenseLayer& a = m_layers[0];
    const DenseLayer& b = m_layers[1];
    const DenseLayer& c = m_layers[2];
    dense(input, a.inputs, a.kernel.data(), a.bias.data(), a.stride, true, hidden1);
    dense(hidden1, b.inputs, b.kernel.data(), b.bias.data(), b.stride, true, hidden2);
    dense(hidden2, c.inputs, c.kernel.data(), c.bias.data(), c.stride, false, linear);
    for (int k = 0; k < kOutputs; ++k) rgb[k] = std::expm1(linear[k]);
}

void NbrdfBrdf::eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query,
                         float* out) const {
    if (!evaluable(wi, wo, query, out)) return;
    float input[kInputs], rgb[kOutputs];
    network_input(wi, wo, input);
    forward(input, rgb);
    // exp(x) - 1 dips below 0 where the network undershoots a black region (clamped when the query
    // asks); the value bound keeps every output finite for unit directions.
    write_rgb_query(rgb, wo.z, query, out);
}

}  // namespace npf
