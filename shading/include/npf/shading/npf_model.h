// A fitted NPF material as it is stored and shaded (paper Eq. 1 with the spectral compression of
// sec. 3.4, Eqs. 11 and 12), per stored channel c (RGB, or one wavelength):
//   f_r(wi, wo) = rho_d[c] + rho_s[c] D_c(theta_h, phi_h) F_c(theta_d) G_c(wi) G_c(wo)
//                 / (cos theta_i cos theta_o)
// where D and G are not stored per channel but as a few basis tables shared by all channels:
//   D_c = max(0, sum_k D.weights[c][k] D.basis[k]),  G_c likewise.
// At full rank that is the fitted tables again (to float precision); at lower rank it is their
// best approximation in the least-squares sense.
//
// Tables and their cell centres (the axis maps and the horizon rule are npf_equation.h's, shared
// with the fitter's NpfFactors::eval):
//   D  [d_theta][d_phi]  theta_h = (pi/2) ((k + 1/2) / d_theta)^2   (square-root mapped)
//                        phi_h   = 2 pi (k + 1/2) / d_phi           (d_phi = 1: isotropic)
//   F  [f_theta]         theta_d = (pi/2) (k + 1/2) / f_theta
//   G  [g_theta][g_phi]  theta   = (pi/2) (k + 1/2) / g_theta,  phi as for D
// Values between centres are bilinear, phi is periodic, theta is clamped at the outer centres,
// except beyond G's last theta centre: there G continues along the line through its last two
// rows (never below 0), so that it can fall to 0 at grazing angles.
//
// Detail layer (optional, format version 2): an additive residual r_c over (u_h, theta_d,
// phi_d), stored like D and G as basis tables over its grid and per-channel weights
// (detail_grid.h); the value is then max(0, NPF + r_c). Without it (detail_grid empty) the model
// is the paper's.
//
// Evaluation interpolates the basis tables first and combines them per channel afterwards (the
// order a texture-based shader follows), so the clamp at 0 applies to the interpolated value.
// The direction work is done once per pair (prepare) and shared by every channel (value).
#pragma once

#include <npf/core/channels.h>
#include <npf/core/vec.h>
#include <npf/shading/detail_grid.h>
#include <npf/shading/npf_pair_angles.h>
#include <npf/shading/npf_equation.h>
#include <npf/shading/table_interpolation.h>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace npf {

// A set of tables (one per channel) written as rank basis tables and per-channel weights: the
// truncated SVD of the cells x channels matrix, singular values folded into the weights.
struct SpectralBasis {
    int rank = 0;
    std::size_t cells = 0;
    std::vector<float> basis;     // [rank][cells], orthonormal columns of U
    std::vector<float> weights;   // [channels][rank], sigma_k v_k(c)
    // Every singular value of the full decomposition (min(cells, channels) of them, descending),
    // for reporting what the truncation dropped.
    std::vector<double> singular_values;
    // sum_{k < rank} sigma_k^2 / sum_k sigma_k^2 (1 when every sigma is 0).
    double kept_ratio = 1.0;

    // The reconstructed table of channel c at one cell, not clamped.
    double at(std::size_t channel, std::size_t cell) const;
};

struct NpfModel {
    Channels channels;
    int d_theta = 0, d_phi = 0;  // D's grid (theta_h, phi_h)
    int f_theta = 0;             // F's grid (theta_d)
    int g_theta = 0, g_phi = 0;  // G's grid (theta, phi)
    std::vector<float> rho_d, rho_s;  // [C]
    std::vector<float> F;             // [C][f_theta]
    SpectralBasis D, G;               // D.cells = d_theta d_phi, G.cells = g_theta g_phi
    // The detail layer: absent when detail_grid is empty (then detail.rank is 0).
    DetailGrid detail_grid;
    SpectralBasis detail;             // detail.cells = detail_grid.cells()
    // Free-form facts carried through the file (source, fitter settings, errors), in order.
    std::vector<std::pair<std::string, std::string>> metadata;

    std::size_t channel_count() const { return rho_d.size(); }
    bool isotropic() const { return d_phi == 1 && g_phi == 1; }
    bool has_detail() const { return !detail_grid.empty(); }

    // G's horizon rule (docs/format.md sec. 3, step 4): beyond its last row centre G continues
    // along the line through its last two rows, reaching 1.5 G_last - 0.5 G_previous at the
    // horizon itself. Where that stays above 0 the albedo grows like 1 / cos(theta_view) in the
    // last fraction of a degree (silhouettes gain light without bound).
    // The value of channel c's G at the horizon in column j (not clamped).
    double g_at_horizon(std::size_t c, int column) const;
    // Whether any channel with a specular term keeps G above 0 at the horizon.
    bool g_open_at_horizon() const;
    // Closes it: scales the last row's cell in each such column (every basis value, so all
    // channels by one factor: the column keeps its colour) until G reaches 0 at the horizon in
    // every channel with a specular term (G_last <= G_previous / 3). Directions up to the centre
    // of the row before the last are unchanged. Returns the number of columns changed.
    int close_g_at_horizon();

    // Throws npf::Error naming `source` when sizes disagree or exceed the caps above, a rank is
    // out of range, a value is not finite or above kMaxMaterialValue in magnitude, rho_d, rho_s
    // or F is negative, wavelengths are not positive and strictly ascending, or singular values
    // are not descending and non-negative, or the largest value the tables can give (value_bound) is above kMaxMaterialValue.
    void validate(const std::string& source) const;
    // An upper bound of f_r cos(theta_i) cos(theta_o) over every pair and channel
    // (npf_value_bound.cpp; core/include/npf/core/brdf.h says why this form).
    double value_bound() const;

    // Ranks up to this many have their interpolated basis values cached in a Lookup; larger ranks
    // are combined corner by corner, slower but the same values. (The texture path of NpfClosure
    // needs the cache, so this is also the largest rank it shades.)
    static constexpr int kInlineRank = 256;
    // The largest detail grid a model may hold (docs/format.md sec. 8): 2^22 cells, 16 MiB of
    // floats per basis table, far above any useful residual and far below what exhausts memory.
    static constexpr std::size_t kMaxDetailCells = std::size_t(1) << 22;
    // The largest D or G table (docs/format.md sec. 8): 2^20 cells (1024 x 1024; the paper's
    // and the production preset's grid is 90 x 180, 64 times smaller), and at most 2^25 basis values (rank x
    // cells, 128 MiB of floats) in any one basis, the detail layer's included. A reader checks
    // these against the header before it allocates anything, so a small file cannot claim gigabytes.
    static constexpr std::size_t kMaxTableCells = std::size_t(1) << 20;
    static constexpr std::size_t kMaxBasisValues = std::size_t(1) << 25;
    // Channels x D's rank x D's cells (the work of building the half-vector sampler, seconds at
    // this cap; a full-rank 195-wavelength anisotropic model at the paper's size is 6e8).
    static constexpr double kMaxSamplerWork = 4294967296.0;

    // Everything about one direction pair that every channel shares. No member initialisers:
    // prepare() fills every field, and the shading hot path should not pay for zeroing.
    struct Lookup {
        using Bilinear = table::Bilinear;
        double cos_i, cos_o, inv_cos_product;  // inv: 1 / (cos_i cos_o)
        // The half vector's angles (phi_h is 0 for an isotropic D) and cos theta_d = wi . h, for
        // the sampler's pdf.
        double theta_h, phi_h, cos_d;
        double u_h;  // sqrt(theta_h / (pi/2)), D's row coordinate in [0, 1]
        // Continuous positions on each table, in cells with centres at integers (rows of G may
        // exceed g_theta - 1: extrapolation), for lookups that interpolate elsewhere (a texture).
        double d_row, d_col, g_i_row, g_i_col, g_o_row, g_o_col;
        Bilinear d, g_i, g_o;
        int f0, f1;
        double f_t;
        // The detail layer's position (has_detail() only): where on each axis, and its corners.
        DetailPosition r_at;
        Trilinear r;
        bool cached;  // basis values below are filled
        // Padded so the three arrays are not 4 KiB apart: loads of one would falsely wait on
        // stores to another (4K aliasing), which cost a third of an evaluation.
        double d_basis[kInlineRank + 8], g_i_basis[kInlineRank + 8], g_o_basis[kInlineRank + 8];
        double r_basis[kInlineRank + 8];
    };

    // Fills `at` for the pair; false when either direction is at or below the horizon or not
    // finite (f_r is then 0). Directions are unit vectors in the local frame. No allocation.
    // With project_bases false the basis values are not projected: value() then combines the
    // tables corner by corner, unless the caller fills the cache itself and sets at.cached (the
    // texture path does).
    bool prepare(const Vec3& wi, const Vec3& wo, Lookup& at, bool project_bases = true) const;
    // prepare() in two halves, for callers that compute the angles of many pairs at once
    // (npf_batch.h): the azimuths this model needs, and the table positions from a pair's angles
    // (pair_angles, npf_pair_angles.h; both directions above the horizon).
    AngleNeeds angle_needs() const { return {d_phi > 1, g_phi > 1, has_detail()}; }
    void position(const PairAngles& angles, Lookup& at, bool project_bases = true) const;
    // The part of prepare() that a pdf needs: the half vector and its angles.
    struct HalfVector {
        double cos_i, cos_o;
        double theta_h, u_h, phi_h;  // as in Lookup
        double cos_d;              // wi . h
    };
    // false below the horizon (as prepare).
    bool half_vector(const Vec3& wi, const Vec3& wo, HalfVector& h) const;
    // f_r of stored channel c at a prepared pair. Inline: a renderer calls it per channel.
    double value(const Lookup& at, std::size_t c) const;
    // value(at, c) of every stored channel into out[c], to the bit, in blocks of channels whose
    // arithmetic vectorises (a spectral model's 195 channels one by one were most of an albedo
    // quadrature's time). `base`, when not null, gets the values without the detail layer.
    void values(const Lookup& at, double* out, double* base = nullptr) const;
    // f_r of every stored channel (channel_count() values); 0 below the horizon.
    void eval_all(const Vec3& wi, const Vec3& wo, double* out) const;
    double eval(std::size_t c, const Vec3& wi, const Vec3& wo) const;

private:
    double value_uncached(const Lookup& at, std::size_t c) const;
};

inline double NpfModel::value(const Lookup& at, std::size_t c) const {
    if (!at.cached) return value_uncached(at, c);
    const float* wd = D.weights.data() + c * std::size_t(D.rank);
    const float* wg = G.weights.data() + c * std::size_t(G.rank);
    double d = 0.0, gi = 0.0, go = 0.0;
    for (int k = 0; k < D.rank; ++k) d += wd[k] * at.d_basis[k];
    for (int k = 0; k < G.rank; ++k) {  // one set of weights for both directions
        gi += wg[k] * at.g_i_basis[k];
        go += wg[k] * at.g_o_basis[k];
    }
    // The clamp at 0 applies to the interpolated, recombined tables (see above).
    const float* f = F.data() + c * std::size_t(f_theta);
    const double fv = f[at.f0] * (1 - at.f_t) + f[at.f1] * at.f_t;
    const double base = equation::value(rho_d[c], rho_s[c], d, fv, gi, go, at.inv_cos_product);
    if (detail.rank == 0) return base;
    const float* wr = detail.weights.data() + c * std::size_t(detail.rank);
    double r = 0.0;
    for (int k = 0; k < detail.rank; ++k) r += wr[k] * at.r_basis[k];
    return equation::with_detail(base, r);
}

}  // namespace npf
