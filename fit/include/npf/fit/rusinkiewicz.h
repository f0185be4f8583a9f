// Rusinkiewicz's half/difference parameterisation (paper sec. 3.1) and the uniform fitting grid
// of the NPF model, in double precision: the fitter's geometry is shared by every wavelength,
// so it is computed once and carefully.
//
// h = normalize(wi + wo) has angles (theta_h, phi_h); d is wi expressed in the frame of h
// (rotated by -phi_h about z, then by -theta_h about y), with angles (theta_d, phi_d). Then
//   cos theta_i = cos theta_h cos theta_d - sin theta_h sin theta_d cos phi_d   (paper Eq. 8)
//   cos theta_o = cos theta_h cos theta_d + sin theta_h sin theta_d cos phi_d   (paper Eq. 9)
// wi is the conditioning direction of the project's convention (docs/conventions.md).
#pragma once

#include <cstddef>

namespace npf {

struct Vec3d {
    double x = 0.0, y = 0.0, z = 0.0;
};

struct HalfDiff {
    double theta_h = 0.0, phi_h = 0.0;  // phi in [0, 2 pi)
    double theta_d = 0.0, phi_d = 0.0;
};

// Unit directions in; angles out. theta_h, theta_d in [0, pi/2] for wi, wo above the horizon.
HalfDiff half_diff_from_directions(const Vec3d& wi, const Vec3d& wo);
// The inverse: unit wi and wo (either may lie below the horizon for angles off the valid set).
void directions_from_half_diff(const HalfDiff& a, Vec3d& wi, Vec3d& wo);

// The uniform grid of samples and factor tables: theta_h is uniform in the square-root
// coordinate u = sqrt(theta_h / (pi/2)) (dense near the specular peak), the other angles are
// uniform. Samples sit at cell centres, which keeps them off the pole (where phi_h is
// undefined) and off the horizon. The paper's grid is 90 x 180 x 90 x 180. An isotropic grid has
// one phi_h cell (phi_h = 0): the material does not depend on it.
struct RusinkiewiczGrid {
    int theta_h = 90, phi_h = 180, theta_d = 90, phi_d = 180;

    bool isotropic() const { return phi_h == 1; }
    std::size_t size() const {
        return std::size_t(theta_h) * std::size_t(phi_h) * std::size_t(theta_d) * std::size_t(phi_d);
    }
    double theta_h_at(int k) const;  // (pi/2) ((k + 1/2) / n)^2
    double phi_h_at(int k) const;    // 2 pi (k + 1/2) / n; 0 when isotropic
    double theta_d_at(int k) const;  // (pi/2) (k + 1/2) / n
    double phi_d_at(int k) const;    // 2 pi (k + 1/2) / n

    // The volume-form sub-weight w_V of paper Eq. 4 at a sample, times the sample's cell volume
    // in (u, phi_h, theta_d, phi_d): d(omega_i) d(omega_o) = 4 sin theta_h sin theta_d cos theta_d
    // d(theta_h) d(phi_h) d(theta_d) d(phi_d), with d(theta_h) = pi u du on this grid. Summed over
    // the samples whose directions are both above the horizon it approximates the measure of
    // those pairs, (2 pi)^2 (isotropic grids count the 2 pi of phi_h in their one cell).
    double volume_weight(int theta_h_index, int theta_d_index) const;
};

}  // namespace npf
