// Neural BRDF reader and evaluator. The weights are read once with the HDF5 C API; evaluation is
// a float forward pass over arrays on the stack, so eval never touches HDF5 and never allocates.
#include <npf/converter/nbrdf_brdf.h>

#include <npf/core/cosine_sampling.h>
#include <npf/core/error.h>
#include <npf/core/input_file.h>

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <mutex>

namespace npf {

namespace {

constexpr int kLayerCount = 3;
// The HDF5 format signature (at offset 0 unless the file has a user block).
constexpr std::uint8_t kHdf5Signature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

// Debian's HDF5 is built without thread safety: one loader at a time.
std::mutex& hdf5_mutex() {
    static std::mutex m;
    return m;
}

// HDF5 prints its whole error stack to stderr by default; a bad file must give exactly one line
// (our npf::Error), so printing is off while we read, and restored afterwards.
class QuietHdf5Errors {
public:
    QuietHdf5Errors() {
        H5Eget_auto2(H5E_DEFAULT, &m_func, &m_data);
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
    ~QuietHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, m_func, m_data); }
    QuietHdf5Errors(const QuietHdf5Errors&) = delete;
    QuietHdf5Errors& operator=(const QuietHdf5Errors&) = delete;

private:
    H5E_auto2_t m_func = nullptr;
    void* m_data = nullptr;
};

// Owns one HDF5 identifier and closes it with the matching function.
class Handle {
public:
    using Closer = herr_t (*)(hid_t);
    Handle(hid_t id, Closer close) : m_id(id), m_close(close) {}
    ~Handle() {
        if (m_id >= 0) m_close(m_id);
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    hid_t get() const { return m_id; }
    bool valid() const { return m_id >= 0; }

private:
    hid_t m_id;
    Closer m_close;
};

// True when every component of `path` ("a/b/c") exists as a link; H5Lexists needs the parents.
bool path_exists(hid_t file, const std::string& path) {
    for (std::size_t end = path.find('/'); ; end = path.find('/', end + 1)) {
        const std::string prefix = path.substr(0, end);
        if (H5Lexists(file, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
        if (end == std::string::npos) return true;
    }
}

std::string dataset_path(int layer, const char* weight) {
    const std::string name = "dense_" + std::to_string(layer);
    return name + "/" + name + "/" + weight + ":0";
}

std::string shape_text(const std::vector<hsize_t>& dims) {
    if (dims.empty()) return "a scalar";
    std::string text;
    for (std::size_t i = 0; i < dims.size(); ++i)
        text += (i ? " x " : "") + std::to_string(static_cast<unsigned long long>(dims[i]));
    return text;
}

// Reads one floating-point dataset as float, with its shape. Throws npf::Error.
std::vector<float> read_float_dataset(hid_t file, const std::string& file_path,
                                      const std::string& name, std::vector<hsize_t>& dims) {
    if (!path_exists(file, name)) throw Error(file_path, "missing dataset " + name);
    Handle dataset(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose);
    if (!dataset.valid()) throw Error(file_path, name + " is not a readable dataset");
    Handle type(H5Dget_type(dataset.get()), H5Tclose);
    if (!type.valid() || H5Tget_class(type.get()) != H5T_FLOAT)
        throw Error(file_path, "dataset " + name + " does not hold floating-point numbers");
    Handle space(H5Dget_space(dataset.get()), H5Sclose);
    const int rank = space.valid() ? H5Sget_simple_extent_ndims(space.get()) : -1;
    if (rank < 0 || rank > 2) throw Error(file_path, "dataset " + name + " has an unusable shape");
    dims.assign(static_cast<std::size_t>(rank), 0);
    if (rank > 0 && H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0)
        throw Error(file_path, "dataset " + name + " has an unusable shape");
    // Shapes are checked by the caller; this only bounds the allocation before reading, by the
    // largest layer accepted (kMaxHiddenUnits squared).
    const hsize_t max_count = hsize_t(NbrdfBrdf::kMaxHiddenUnits) * NbrdfBrdf::kMaxHiddenUnits;
    hsize_t count = 1;
    for (hsize_t d : dims) {
        if (d > max_count || count * d > max_count)
            throw Error(file_path, "dataset " + name + " is too large (" + shape_text(dims) + ")");
        count *= d;
    }
    std::vector<float> values(static_cast<std::size_t>(count));
    if (count > 0 && H5Dread(dataset.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                             values.data()) < 0)
        throw Error(file_path, "cannot read dataset " + name + " (file truncated or damaged)");
    return values;
}

// A string attribute of the root group (Keras writes `keras_version` and `backend`), or "" when
// it is absent or not a string: it is only shown by `npf info`.
std::string root_string_attribute(hid_t file, const char* name) {
    if (H5Aexists(file, name) <= 0) return {};
    Handle attribute(H5Aopen(file, name, H5P_DEFAULT), H5Aclose);
    if (!attribute.valid()) return {};
    Handle type(H5Aget_type(attribute.get()), H5Tclose);
    Handle space(H5Aget_space(attribute.get()), H5Sclose);
    if (!type.valid() || !space.valid() || H5Tget_class(type.get()) != H5T_STRING ||
        H5Sget_simple_extent_npoints(space.get()) != 1)
        return {};
    Handle memory_type(H5Tcopy(H5T_C_S1), H5Tclose);
    if (H5Tis_variable_str(type.get()) > 0) {
        H5Tset_size(memory_type.get(), H5T_VARIABLE);
        char* text = nullptr;
        if (H5Aread(attribute.get(), memory_type.get(), &text) < 0 || text == nullptr) return {};
        std::string value(text);
        H5free_memory(text);
        return value;
    }
    const std::size_t size = H5Tget_size(type.get());
    if (size == 0 || size > 4096) return {};
    std::vector<char> text(size + 1, '\0');
    H5Tset_size(memory_type.get(), size + 1);  // room for the terminator HDF5 adds
    if (H5Aread(attribute.get(), memory_type.get(), text.data()) < 0) return {};
    return std::string(text.data());
}

bool all_finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
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

    std::lock_guard<std::mutex> lock(hdf5_mutex());
    QuietHdf5Errors quiet;
    if (H5Fis_hdf5(path.c_str()) <= 0) throw Error(path, "not an HDF5 file");
    Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) throw Error(path, "cannot read the HDF5 file (truncated or damaged)");

    auto brdf = std::unique_ptr<NbrdfBrdf>(new NbrdfBrdf());
    int inputs = kInputs;
    for (int k = 0; k < kLayerCount; ++k) {
        const bool last = k + 1 == kLayerCount;
        const std::string kernel_name = dataset_path(k + 1, "kernel");
        const std::string bias_name = dataset_path(k + 1, "bias");
        std::vector<hsize_t> kernel_dims, bias_dims;
        std::vector<float> kernel = read_float_dataset(file.get(), path, kernel_name, kernel_dims);
        std::vector<float> bias = read_float_dataset(file.get(), path, bias_name, bias_dims);

        const std::string wanted = std::to_string(inputs) + " x " +
                                   (last ? std::to_string(kOutputs) : std::string("n"));
        const bool kernel_ok = kernel_dims.size() == 2 && kernel_dims[0] == hsize_t(inputs) &&
                               (last ? kernel_dims[1] == hsize_t(kOutputs)
                                     : kernel_dims[1] >= 1 && kernel_dims[1] <= hsize_t(kMaxHiddenUnits));
        if (!kernel_ok)
            throw Error(path, kernel_name + " has shape " + shape_text(kernel_dims) + ", expected " +
                                  wanted + (last ? "" : " with 1 <= n <= " + std::to_string(kMaxHiddenUnits)) +
                                  " (network 6 -> n1 -> n2 -> 3)");
        const int units = static_cast<int>(kernel_dims[1]);
        if (bias_dims.size() != 1 || bias_dims[0] != hsize_t(units))
            throw Error(path, bias_name + " has shape " + shape_text(bias_dims) + ", expected " +
                                  std::to_string(units) + " (the kernel's units)");
        for (const std::vector<float>* values : {&kernel, &bias}) {
            const auto bad = std::find_if(values->begin(), values->end(),
                                          [](float v) { return !std::isfinite(v); });
            if (bad != values->end())
                throw Error(path, "non-finite weight in " +
                                      (values == &kernel ? kernel_name : bias_name) + " at index " +
                                      std::to_string(bad - values->begin()));
        }
        DenseLayer& layer = brdf->m_layers[k];
        layer.inputs = inputs;
        layer.units = units;
        layer.stride = padded(units);
        layer.kernel.assign(static_cast<std::size_t>(inputs) * layer.stride, 0.f);
        for (int i = 0; i < inputs; ++i)
            std::copy_n(kernel.begin() + static_cast<std::ptrdiff_t>(i) * units, units,
                        layer.kernel.begin() + static_cast<std::ptrdiff_t>(i) * layer.stride);
        layer.bias.assign(static_cast<std::size_t>(layer.stride), 0.f);
        std::copy(bias.begin(), bias.end(), layer.bias.begin());
        inputs = units;
    }
    // A deeper network would be evaluated wrongly, not approximately: refuse it.
    const std::string extra = "dense_" + std::to_string(kLayerCount + 1);
    if (path_exists(file.get(), extra))
        throw Error(path, "has a layer " + extra + ": expected exactly 3 dense layers (6 -> n1 -> n2 -> 3)");

    const std::string keras_version = root_string_attribute(file.get(), "keras_version");
    const std::string backend = root_string_attribute(file.get(), "backend");

    const int n1 = brdf->m_layers[0].units, n2 = brdf->m_layers[1].units;
    const int weights = (kInputs + 1) * n1 + (n1 + 1) * n2 + (n2 + 1) * kOutputs;
    BrdfInfo& info = brdf->m_info;
    info.format = "nbrdf";
    info.path = path;
    // The networks carry no description; the material's name is the file name.
    info.description = std::filesystem::path(path).stem().string();
    info.isotropic = true;
    info.channels = Channels::rgb();
    info.file_bytes = file_size;
    info.details = {
        {"network", "6 -> " + std::to_string(n1) + " (ReLU) -> " + std::to_string(n2) +
                        " (ReLU) -> 3 (linear), then exp(x) - 1"},
        {"weights", std::to_string(weights)},
        {"input", "half vector (phi_h = 0) and difference vector of wo"},
        {"output", "f_r in 1/sr, R G B"},
        {"sampling", "cosine-weighted"},
    };
    if (!keras_version.empty())
        info.details.emplace_back("keras", keras_version + (backend.empty() ? "" : " (" + backend + ")"));
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
    const std::size_t n = query.size();
    if (!(wi.z > 0.f) || !(wo.z > 0.f) || !all_finite(wi) || !all_finite(wo)) {
        std::fill(out, out + n, 0.f);
        return;
    }
    float input[kInputs], rgb[kOutputs];
    network_input(wi, wo, input);
    forward(input, rgb);
    const float cos_o = wo.z;
    for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t i0 = query.index0[k], i1 = query.index1[k];
        const float w1 = query.weight1[k];
        const float a = i0 < kOutputs ? rgb[i0] : 0.f;
        const float b = i1 < kOutputs ? rgb[i1] : 0.f;
        float v = (w1 == 0.f ? a : (1.f - w1) * a + w1 * b) * cos_o;
        if (!std::isfinite(v)) v = 0.f;  // exp overflow on absurd weights; never emit inf/NaN
        // exp(x) - 1 dips below 0 where the network undershoots a black region.
        if (query.clamp_negative && v < 0.f) v = 0.f;
        out[k] = v;
    }
}

// ---- Sampling ----------------------------------------------------------------------------
// The network has no inverse; cosine-weighted sampling is exact for the diffuse part, never zero
// where the BRDF is not, and keeps pdf and sample trivially consistent (as for MERL files).

float NbrdfBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
    if (!(wi.z > 0.f) || !(wo.z > 0.f)) return 0.f;
    return wo.z * (1.f / kPi);
}

bool NbrdfBrdf::sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                       float* weight) const {
    return sample_cosine_hemisphere(*this, wi, u, query, s, weight);
}

}  // namespace npf
