// Writes an RGL `.bsdf` file from any BRDF source ("virtual acquisition", docs/rgl-format.md
// sec. 9): the NDF and projected-area tables, a theta_i grid, the VNDF
// and luminance warps and the data, built exactly as the reference readers will read them, so
// that reading the file back reproduces the source at the data nodes to float precision.
// Valid for every reader: float32 tables, u8 description and jacobian, 8-byte aligned
// payloads, isotropic files with one phi_i entry, anisotropic ones spanning [-pi, pi].
#pragma once

#include <npf/core/brdf.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace npf {

enum class AnisotropyMode { Auto, Isotropic, Anisotropic };

struct RglWriterOptions {
    // What the file stores: RGB (an `rgb` field) or these wavelengths (`spectra`).
    Channels channels = Channels::rgb();
    // Auto asks the source's info() and checks it numerically (looks_isotropic).
    AnisotropyMode anisotropy = AnisotropyMode::Auto;
    int phi_count = 24;        // anisotropic: phi_i nodes spanning [-pi, pi] (both ends included)
    int theta_count = 8;       // theta_i nodes in [0, pi/2], equal steps in projected area
    int ndf_size = 128;        // ndf and sigma columns (u_theta nodes)
    int ndf_rows = 64;         // anisotropic ndf and sigma rows (u_phi nodes); isotropic files use 2
    int vndf_size = 128;       // vndf inner grid
    int data_size = 32;        // data grid (square)
    std::string description;   // empty: the source's description
    // The source's normal distribution D(m), if known (analytic microfacet models). Without it
    // D is recovered from retro-reflection by power iteration (sec. 9 W1 b).
    std::function<float(const Vec3& m)> ndf;
    int power_iterations = 12;
    int threads = 0;           // 0: all hardware threads
    // Called with the fraction done (0..1) from the writing thread.
    std::function<void(double)> progress;
};

struct RglWriteReport {
    std::string path;
    bool isotropic = true;
    std::uint64_t bytes = 0;
    std::vector<float> theta_i, phi_i;
    std::uint64_t data_nodes = 0, valid_nodes = 0;   // data nodes, and those with wo above the horizon
    double seconds = 0.0;
};

// Throws npf::Error naming `path` (bad options, a source that cannot provide the channels,
// a write failure). The file appears atomically.
RglWriteReport write_rgl(const Brdf& source, const std::string& path, const RglWriterOptions& options);

// Whether f_r is unchanged by rotating both directions about the normal: compares the
// source's first channels at `pairs` random direction pairs and random rotations. Relative
// tolerance on values above 1e-6 of the largest one seen.
bool looks_isotropic(const Brdf& source, int pairs = 2000, double tolerance = 1e-3);

}  // namespace npf
