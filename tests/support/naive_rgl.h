// A deliberately simple, slow, double-precision re-implementation of the RGL measured-BRDF
// algorithm, written from the published description (docs: rgl-format.md, secs. 0 to 8) and
// NOT from the project's reader (materials/src/rgl_brdf.cpp, piecewise_linear_2d.cpp). It
// exists only so that tests can check the reader against an independent evaluation.
//
// Everything is written for obviousness, not speed: parameter blends loop explicitly over
// the 2^P corner slices, interval searches are linear scans, CDFs are accumulated and kept in
// double, and no state is shared between calls.
//
// Only npf::TensorFile (field lookup and numeric conversion) is used from the project.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace npf::testing {

struct Vec3d {
    double x = 0.0, y = 0.0, z = 0.0;
};

// Offsets added to the intermediate coordinates of an evaluation, for measuring how sensitive
// a value is to rounding inside a float32 implementation (tests use it to tell float
// conditioning from real disagreements). eval_cos / pdf: u_h is offset before the VNDF
// inversion, xi after it (u1, u2, ramp unused). sample: u1, u2 before the luminance warp, xi
// after it, u_h after the VNDF warp, and `ramp` float32 cancellation errors in the quadratic
// branch of Ramp (sec. 3.4): each solution tau moves by ramp * 2^-23 * max(a, b) / |a - b|,
// the rounding error of `a - sqrt(...)` in float divided by `a - b`, which the published
// formula suffers when |a - b| is just above its 1e-4 (a + b) threshold.
struct NaivePerturbation {
    double xi_x = 0.0, xi_y = 0.0, uh_x = 0.0, uh_y = 0.0, u1 = 0.0, u2 = 0.0, ramp = 0.0;
};

// The conditional piecewise-bilinear 2-D table of rgl-format.md sec. 3 ("PL2D<P>"): a stack of
// H x W node tables indexed by P conditioning parameters, in file layout [N_0]..[N_{P-1}][H][W].
class NaivePl2d {
public:
    NaivePl2d() = default;
    // `grids` are the parameter grids (outermost first); `values` has prod(N_p) * H * W
    // entries. With `normalize`, every slice becomes a density on the unit square (sec. 3.2).
    NaivePl2d(std::vector<std::vector<double>> grids, std::size_t height, std::size_t width,
              std::vector<double> values, bool normalize);

    std::size_t width() const { return m_width; }
    std::size_t height() const { return m_height; }

    // Sec. 3.3: bilinear interpolation of the blended slice at u = (ux, uy) (clamped to [0,1]).
    double eval(double ux, double uy, const std::vector<double>& params) const;
    // Sec. 3.4, forward warp of xi (normalized tables only). Writes the point and its density.
    // `ramp_error`: see NaivePerturbation::ramp.
    void sample(double xi_x, double xi_y, const std::vector<double>& params, double& ux,
                double& uy, double& density, double ramp_error = 0.0) const;
    // Sec. 3.4, exact inverse of sample(): xi of the point u and the density at u.
    void invert(double ux, double uy, const std::vector<double>& params, double& xi_x,
                double& xi_y, double& density) const;

    // Clamp of xi in sample() (powitacq uses about 6e-8).
    static constexpr double kSampleEpsilon = 6e-8;

private:
    struct Corner {
        std::size_t slice = 0;
        double weight = 0.0;
    };
    // Sec. 3.1: the 2^P corner slices and their multilinear weights.
    std::vector<Corner> corners(const std::vector<double>& params) const;
    // Sum over corners of weight * table[slice * per_slice + k].
    static double blend(const std::vector<Corner>& cs, const std::vector<double>& table,
                        std::size_t per_slice, std::size_t k);

    std::vector<std::vector<double>> m_grids;
    std::size_t m_height = 0, m_width = 0, m_slices = 0;
    bool m_normalized = false;
    std::vector<double> m_data;      // [slice][H][W]; normalized to unit integral if m_normalized
    std::vector<double> m_row_cdf;   // [slice][H][W]  C
    std::vector<double> m_row_int;   // [slice][H]     Rw
    std::vector<double> m_marginal;  // [slice][H]     M
};

class NaiveRgl {
public:
    // Throws (npf::Error from TensorFile, std::runtime_error for shape problems).
    static NaiveRgl load(const std::string& path);

    // f_r(wi, wo) cos(theta_o) per channel (sec. 5). `wavelengths` empty: the stored channels
    // (R, G, B for RGB files, the stored wavelengths for spectral files); otherwise the given
    // wavelengths in nm (spectral files only), interpolated linearly and constant outside the
    // stored range (sec. 8). `clamp`: negative interpolated values become 0.
    std::vector<double> eval_cos(const Vec3d& wi, const Vec3d& wo,
                                 const std::vector<double>& wavelengths, bool clamp,
                                 const NaivePerturbation& perturb = {}) const;
    // Solid-angle density of sample() (sec. 6).
    double pdf(const Vec3d& wi, const Vec3d& wo, const NaivePerturbation& perturb = {}) const;
    // Sec. 6. Returns false when no direction above the horizon results. With `weight` not
    // null, writes f_r cos / pdf per channel (channels chosen as in eval_cos).
    bool sample(const Vec3d& wi, double u1, double u2, Vec3d& wo, double& pdf,
                std::vector<double>* weight = nullptr,
                const std::vector<double>& wavelengths = {}, bool clamp = true,
                const NaivePerturbation& perturb = {}) const;

    bool isotropic = true;
    int reduction = 1;       // 1, or 2 / 4 for folded anisotropic files
    bool jacobian = true;
    bool spectral = false;
    std::vector<double> phi_i, theta_i, stored_wavelengths;

private:
    // The published algorithm's steps shared by eval_cos and pdf: fold, half vector, angles,
    // u-space coordinates and the VNDF inversion.
    struct Lookup {
        Vec3d wi, wh;
        double theta_i = 0, phi_i = 0;
        double uh_x = 0, uh_y = 0, ui_x = 0, ui_y = 0;
        double xi_x = 0, xi_y = 0, vndf_density = 0;
    };
    Lookup lookup(const Vec3d& wi_in, const Vec3d& wo_in, const NaivePerturbation& perturb) const;

    std::vector<double> channel_params(const std::vector<double>& wavelengths) const;
    std::vector<double> data_values(double xi_x, double xi_y, double phi_in, double theta_in,
                                    const std::vector<double>& wavelengths, bool clamp) const;

    NaivePl2d m_ndf, m_sigma, m_vndf, m_luminance, m_data;
};

}  // namespace npf::testing
