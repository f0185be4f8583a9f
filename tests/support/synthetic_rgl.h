// Small, valid RGL `.bsdf` files of every kind the reader supports, made in memory for tests:
// isotropic and anisotropic (phi_i reductions 1, 2, 4), RGB and spectral, jacobian 0 or 1.
// The tables follow an analytic anisotropic microfacet-like lobe plus a diffuse floor, so
// that sampling tests see realistic, peaked densities. Not a physically exact writer (that is
// the converter's RGL writer); only structurally what every reference reader accepts.
#pragma once

#include <npf/materials/tensor_file.h>

#include <cstdint>
#include <string>
#include <vector>

namespace npf::testing {

struct SyntheticRglSpec {
    int phi_count = 1;         // 1 (or 2): isotropic; >= 3: anisotropic. phi_i is [0], or
                               // [-pi, pi] (two equal slices), or phi_count values from -pi
                               // to -pi + 2 pi / reduction inclusive
    int reduction = 1;         // anisotropic only: phi_i covers 2 pi / reduction
    int theta_count = 6;       // theta_i nodes in [0, pi/2]
    int ndf_size = 64;         // ndf and sigma: [rows, ndf_size]; rows (u_phi nodes) = 2 if
                               // isotropic (equal rows), else ndf_size, covering the full circle
    int vndf_size = 32;        // vndf inner grid: vndf_size x vndf_size
    int data_size = 16;        // data grid: data_size x data_size
    bool spectral = false;
    std::vector<float> wavelengths = {400.f, 500.f, 600.f, 700.f};
    bool jacobian = true;
    float alpha_x = 0.3f, alpha_y = 0.3f;  // lobe widths along tangent / bitangent
    std::string description = "synthetic test material";
};

// The fields of such a file, ready to serialize or to modify before writing.
// Field order: description, jacobian, phi_i, theta_i, ndf, sigma, vndf, luminance, then rgb,
// or wavelengths and spectra. Grid sizes of 1 are allowed (they give files a reader must
// reject); `reduction` may be any positive number (only 1, 2, 4 give valid files).
TensorFileWriter make_synthetic_rgl(const SyntheticRglSpec& spec);
// Writes it atomically to `path` and returns `path`.
std::string write_synthetic_rgl(const SyntheticRglSpec& spec, const std::string& path);

// The same fields one by one, for tests that build malformed variants: edit, drop, reorder
// or duplicate entries, then turn them into a writer.
struct SyntheticField {
    std::string name;
    DType dtype = DType::F32;
    std::vector<std::uint64_t> shape;
    std::vector<std::uint8_t> bytes;  // the payload in host byte order, C order

    std::vector<float> floats() const;              // dtype must be F32
    void set_floats(const std::vector<float>& v);   // makes the field F32; shape kept
};
std::vector<SyntheticField> synthetic_rgl_fields(const SyntheticRglSpec& spec);
TensorFileWriter to_writer(const std::vector<SyntheticField>& fields);
// The named field, or nullptr.
SyntheticField* find_field(std::vector<SyntheticField>& fields, const std::string& name);
// Removes the named field; returns false if there was none.
bool remove_field(std::vector<SyntheticField>& fields, const std::string& name);

// A fresh temporary folder; every folder handed out is removed when the test process exits,
// unless NPF_KEEP_TEST_FILES is set (to look at what a failing test wrote).
std::string temporary_folder(const std::string& tag);
// Path of a file in ../shared/data (NPF_SHARED_DATA env var overrides), or "" if absent.
std::string shared_data_file(const std::string& relative);

}  // namespace npf::testing
