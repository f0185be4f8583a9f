// Anisotropic GGX and Beckmann NDFs with Smith masking. Everything is evaluated in double and
// in the "stretched" form (x^2/ax^2 + y^2/ay^2 instead of tan^2 theta and cos^2 phi), which
// stays exact at the normal and finite at the horizon for roughness down to 1e-4.
#include <npf/materials/analytic/microfacet.h>

#include <cmath>
#include <limits>

namespace npf {

namespace {

constexpr double kInvSqrtPi = 0.56418958354775628695;

struct LobeVec {
    double x, y, z;
};

// Surface frame -> lobe frame: the lobe's tangent is (cos r, sin r, 0).
LobeVec to_lobe(const MicrofacetNdf& ndf, const Vec3& v) {
    if (ndf.rotation == 0.f) return {v.x, v.y, v.z};
    const double c = std::cos(double(ndf.rotation)), s = std::sin(double(ndf.rotation));
    return {c * v.x + s * v.y, -s * v.x + c * v.y, double(v.z)};
}

Vec3 from_lobe(const MicrofacetNdf& ndf, double x, double y, double z) {
    if (ndf.rotation == 0.f) return {float(x), float(y), float(z)};
    const double c = std::cos(double(ndf.rotation)), s = std::sin(double(ndf.rotation));
    return {float(c * x - s * y), float(s * x + c * y), float(z)};
}

// The squared projected roughness times sin^2 theta of a direction: alpha(phi)^2 (x^2 + y^2).
double stretched_tangent_sq(const MicrofacetNdf& ndf, const LobeVec& w) {
    const double ax = ndf.alpha_x, ay = ndf.alpha_y;
    return ax * ax * w.x * w.x + ay * ay * w.y * w.y;
}

// sigma(w) = integral max(0, w.m) D(m) dm for any w (also below the horizon, where it is the
// area of the facets the downward direction sees from behind). Closed forms:
//  GGX:      (z + sqrt(z^2 + s^2)) / 2
//  Beckmann: z erfc(-z/s) / 2 + s exp(-z^2/s^2) / (2 sqrt(pi))
// with s^2 = ax^2 x^2 + ay^2 y^2 (in the lobe frame). Both satisfy sigma(w) - sigma(-w) = z.
double sigma_of(const MicrofacetNdf& ndf, const LobeVec& w) {
    const double s2 = stretched_tangent_sq(ndf, w);
    const double z = w.z;
    if (ndf.type == MicrofacetDistribution::Ggx) return 0.5 * (z + std::sqrt(z * z + s2));
    if (s2 <= 0.0) return z > 0.0 ? z : 0.0;
    const double s = std::sqrt(s2);
    const double a = z / s;
    return 0.5 * z * std::erfc(-a) + 0.5 * s * kInvSqrtPi * std::exp(-a * a);
}

// Lambda for z > 0, written without the cancellation of sigma/z - 1.
double lambda_of(const MicrofacetNdf& ndf, const LobeVec& w) {
    const double z = std::fabs(w.z);
    if (z == 0.0) return std::numeric_limits<double>::infinity();
    const double s2 = stretched_tangent_sq(ndf, w);
    if (s2 <= 0.0) return 0.0;
    if (ndf.type == MicrofacetDistribution::Ggx) {
        const double t = s2 / (z * z);  // alpha^2 tan^2 theta
        return t / (2.0 * (1.0 + std::sqrt(1.0 + t)));
    }
    const double a = z / std::sqrt(s2);  // 1 / (alpha tan theta)
    const double l = 0.5 * (std::exp(-a * a) * kInvSqrtPi / a - std::erfc(a));
    return l > 0.0 ? l : 0.0;
}

}  // namespace

float MicrofacetNdf::eval(const Vec3& m) const {
    if (!(m.z > 0.f)) return 0.f;
    const LobeVec l = to_lobe(*this, m);
    const double ax = alpha_x, ay = alpha_y;
    const double px = l.x / ax, py = l.y / ay;
    const double z2 = l.z * l.z;
    if (type == MicrofacetDistribution::Ggx) {
        // 1 / (pi ax ay cos^4 (1 + tan^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2))^2)
        const double q = px * px + py * py + z2;
        return float(1.0 / (kPiD * ax * ay * q * q));
    }
    const double e = (px * px + py * py) / z2;  // tan^2 theta (cos^2 phi / ax^2 + sin^2 phi / ay^2)
    if (!(e < 700.0)) return 0.f;  // exp underflows in double; also guards z2 == 0
    return float(std::exp(-e) / (kPiD * ax * ay * z2 * z2));
}

float MicrofacetNdf::lambda(const Vec3& w) const { return float(lambda_of(*this, to_lobe(*this, w))); }

float MicrofacetNdf::smith_g1(const Vec3& w, const Vec3& m) const {
    if (!(dot(w, m) > 0.f)) return 0.f;
    const double l = lambda_of(*this, to_lobe(*this, w));
    return float(1.0 / (1.0 + l));
}

float MicrofacetNdf::projected_area(const Vec3& w) const {
    const double s = sigma_of(*this, to_lobe(*this, w));
    return float(s > 0.0 ? s : 0.0);
}

// Slopes (p, q) = -(m.x, m.y) / m.z have the density D(m) cos^4(theta_m), which for both
// distributions is the unit-roughness isotropic one stretched by (ax, ay); its radius has a
// closed-form inverse CDF: GGX r^2 = u / (1 - u), Beckmann r^2 = -log(1 - u).
Vec3 MicrofacetNdf::sample(const Vec2& u) const {
    const double u1 = u.x < 0.f ? 0.0 : (u.x >= 1.f ? 1.0 - 1e-9 : double(u.x));
    const double r2 = type == MicrofacetDistribution::Ggx ? u1 / (1.0 - u1) : -std::log1p(-u1);
    const double r = std::sqrt(r2);
    const double phi = 2.0 * kPiD * double(u.y);
    const double x = alpha_x * r * std::cos(phi);
    const double y = alpha_y * r * std::sin(phi);
    const double inv = 1.0 / std::sqrt(1.0 + x * x + y * y);
    return from_lobe(*this, x * inv, y * inv, inv);
}

}  // namespace npf
