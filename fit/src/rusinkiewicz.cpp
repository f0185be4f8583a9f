#include <npf/fit/rusinkiewicz.h>

#include <npf/core/vec.h>
#include <npf/shading/npf_equation.h>

#include <cmath>

namespace npf {

namespace {

double wrap_two_pi(double phi) {
    phi = std::fmod(phi, kTwoPiD);
    return phi < 0.0 ? phi + kTwoPiD : phi;
}

// Angle of a unit vector from +z, accurate near the pole (2 asin(|w - z| / 2)).
double elevation(const Vec3d& w) {
    const double d = std::sqrt(w.x * w.x + w.y * w.y + (w.z - 1.0) * (w.z - 1.0));
    return 2.0 * std::asin(std::fmin(1.0, 0.5 * d));
}

}  // namespace

HalfDiff half_diff_from_directions(const Vec3d& wi, const Vec3d& wo) {
    Vec3d h{wi.x + wo.x, wi.y + wo.y, wi.z + wo.z};
    const double len = std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
    h = {h.x / len, h.y / len, h.z / len};
    HalfDiff a;
    a.theta_h = elevation(h);
    a.phi_h = wrap_two_pi(std::atan2(h.y, h.x));
    // d = R_y(-theta_h) R_z(-phi_h) wi.
    const double cp = std::cos(a.phi_h), sp = std::sin(a.phi_h);
    const double ct = std::cos(a.theta_h), st = std::sin(a.theta_h);
    const double x1 = cp * wi.x + sp * wi.y, y1 = -sp * wi.x + cp * wi.y, z1 = wi.z;
    const Vec3d d{ct * x1 - st * z1, y1, st * x1 + ct * z1};
    a.theta_d = elevation(d);
    a.phi_d = wrap_two_pi(std::atan2(d.y, d.x));
    return a;
}

void directions_from_half_diff(const HalfDiff& a, Vec3d& wi, Vec3d& wo) {
    const double sd = std::sin(a.theta_d), cd = std::cos(a.theta_d);
    const Vec3d d{sd * std::cos(a.phi_d), sd * std::sin(a.phi_d), cd};
    // wi = R_z(phi_h) R_y(theta_h) d.
    const double ct = std::cos(a.theta_h), st = std::sin(a.theta_h);
    const double x1 = ct * d.x + st * d.z, z1 = -st * d.x + ct * d.z;
    const double cp = std::cos(a.phi_h), sp = std::sin(a.phi_h);
    wi = {cp * x1 - sp * d.y, sp * x1 + cp * d.y, z1};
    const Vec3d h{st * cp, st * sp, ct};
    const double k = 2.0 * (wi.x * h.x + wi.y * h.y + wi.z * h.z);
    wo = {k * h.x - wi.x, k * h.y - wi.y, k * h.z - wi.z};
}

// The fitter samples at the stored tables' cell centres (npf_equation.h).
double RusinkiewiczGrid::theta_h_at(int k) const { return equation::theta_h_centre(k, theta_h); }

double RusinkiewiczGrid::phi_h_at(int k) const { return isotropic() ? 0.0 : equation::phi_centre(k, phi_h); }

double RusinkiewiczGrid::theta_d_at(int k) const { return equation::theta_centre(k, theta_d); }

double RusinkiewiczGrid::phi_d_at(int k) const { return equation::phi_centre(k, phi_d); }

double RusinkiewiczGrid::volume_weight(int theta_h_index, int theta_d_index) const {
    const double u = (theta_h_index + 0.5) / theta_h;
    const double du = 1.0 / theta_h;
    const double d_theta_d = kHalfPiD / theta_d, d_phi_h = kTwoPiD / phi_h, d_phi_d = kTwoPiD / phi_d;
    const double th = theta_h_at(theta_h_index), td = theta_d_at(theta_d_index);
    return 4.0 * std::sin(th) * std::sin(td) * std::cos(td) * (kPiD * u * du) * d_phi_h * d_theta_d * d_phi_d;
}

}  // namespace npf
