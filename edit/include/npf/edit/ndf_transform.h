// Editing the NDF by a linear transform (paper sec. 4.3.1; docs/editing.md has the maths).
//
// Convention: M acts on microfacet normals. The edited material is the microsurface whose
// normals are those of the original mapped by h' = M h / |M h| (the "normal matrix"; in terms
// of the surface geometry, points move by M^-T). Its NDF follows from the projected-area
// density p(h) = D(h) cos theta_h, which transforms like any density on the sphere (the LTC
// rule, Heitz et al. 2016):
//   p'(h) = p(h_o) |det M^-1| / |M^-1 h|^3,   h_o = M^-1 h / |M^-1 h|,
//   D'(h) = p'(h) / cos theta_h.
// For tangent-plane maps M = diag(M2, 1) (stretch, rotation, roughness scale, skew) this is
// D'(h) = D(h_o) |det M2^-1| / |M^-1 h|^4, the projected area stays exactly 1 and Smith's
// masking transforms by the ray map: G'(w) = G(w_o), w_o = M^T w / |M^T w|. The stored G is
// transformed that way (it need not be Smith's; visibility is affine-invariant).
// On the tables, D' and G' are sampled at the cell centres with the model's own bilinear
// interpolation of the original, D' is renormalised to projected area 1 on the stored grid (the
// original's area goes into rho_s, so the BRDF's scale is kept), and D and G are compressed
// again across channels by the SVD.
#pragma once

#include <npf/edit/edit_record.h>
#include <npf/shading/npf_model.h>

#include <array>
#include <string>
#include <vector>

namespace npf::edit {

// Row-major 3 x 3 matrix in the local frame (x tangent, y bitangent, z normal).
struct Mat3 {
    std::array<double, 9> m{1, 0, 0, 0, 1, 0, 0, 0, 1};
    double operator()(int row, int col) const { return m[std::size_t(row * 3 + col)]; }
    double& operator()(int row, int col) { return m[std::size_t(row * 3 + col)]; }
    static Mat3 identity() { return Mat3{}; }
    bool operator==(const Mat3& o) const { return m == o.m; }
};

// The friendly forms, all tangent-plane maps of the normals:
// stretch the NDF (and so the highlight and the roughness) by `tangent` along x and by
// `bitangent` along y: GGX alpha_x -> tangent alpha_x, alpha_y -> bitangent alpha_y.
Mat3 stretch_matrix(double tangent, double bitangent);
// Rotates the NDF about the normal by `degrees`, from the tangent towards the bitangent:
// D'(phi_h) = D(phi_h - angle).
Mat3 rotation_matrix(double degrees);
// Scales the roughness in every direction: below 1 sharpens the highlight, above 1 blurs it.
Mat3 roughness_matrix(double scale);

// "[[a, b, c], [d, e, f], [g, h, i]]" with up to 6 significant digits.
std::string matrix_text(const Mat3& m);

enum class Recompress {
    KeepRank,   // the input's ranks (an edit of a rank-r model has rank r: nothing lost)
    KeptRatio,  // the smallest rank that keeps the input's cumulative contribution ratio
};

struct NdfTransformOptions {
    // Azimuth cells of D and G when an isotropic model becomes anisotropic; 0 gives twice the
    // theta cells (the paper's 90 x 180).
    int phi_cells = 0;
    Recompress recompress = Recompress::KeepRank;
};

// The transformed model. Throws npf::Error (source "ndf transform") for a matrix that is not
// finite, is singular or maps the normal onto the horizon (M(2,2) = 0), or for options out of
// range. The identity (and any multiple of it) returns the model unchanged, bit for bit; so do
// rotations of an isotropic model. Matrices with a tilt (nonzero M(0,2), M(1,2), M(2,0),
// M(2,1)) are applied by the general formula, cut at the horizon and renormalised; the record
// warns that G is then only approximately consistent.
NpfModel transform_ndf(const NpfModel& model, const Mat3& m, const NdfTransformOptions& options = {},
                       EditRecord* record = nullptr);

// The projected area of each channel's D on the stored grid: the midpoint rule over D's cells,
// sum D_c cos theta_h sin theta_h (pi u du) dphi, with D_c clamped at 0 as the model evaluates
// it (the fitter's gauge uses the same quadrature).
std::vector<double> projected_area(const NpfModel& model);

}  // namespace npf::edit
