// Small fixed-size vectors for direction work. Float, because every table we read is float32
// and renderers hand us float directions; functions that need more care (elevation near the
// normal, normalisation of nearly opposite vectors) are written to stay accurate in float.
#pragma once

#include <cmath>

namespace npf {

struct Vec2 {
    float x = 0.f, y = 0.f;
};

struct Vec3 {
    float x = 0.f, y = 0.f, z = 0.f;

    Vec3() = default;
    constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}

    Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    Vec3 operator*(float s) const { return {x * s, y * s, z * s}; }
    Vec3 operator-() const { return {-x, -y, -z}; }
};

inline float dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float length(const Vec3& a) { return std::sqrt(dot(a, a)); }
// Divides rather than multiplying by the reciprocal: normalize((0, 0, 2z)) must give z = 1
// exactly, or the half vector of an exact mirror pair leaves the pole and the square-root
// warp (u = sqrt(2 theta / pi)) magnifies the 1-ulp error into a visibly different pdf.
inline Vec3 normalize(const Vec3& a) {
    const float l = length(a);
    return {a.x / l, a.y / l, a.z / l};
}

// A direction given in double (a file, a numpy array) as a unit float vector, the one way npf
// reads directions from callers (npf eval, the Python package): the length as the root of the sum
// of squares where those stay well inside double's range, else by hypot, so that components of
// 1e308 (or 1e-310) are a direction like any other (their squares would overflow, or vanish);
// then a division per component. (hypot everywhere cost the Python package's batched eval a
// third of its time.) False for a direction of zero length or with a NaN component.
inline bool squares_need_no_hypot(double squares) { return squares > 1e-290 && squares < 1e290; }
inline bool unit_direction(double x, double y, double z, Vec3& out) {
    const double squares = x * x + y * y + z * z;
    const double l = squares_need_no_hypot(squares) ? std::sqrt(squares) : std::hypot(x, y, z);
    if (!(l > 0.0)) return false;
    out = Vec3(float(x / l), float(y / l), float(z / l));
    return true;
}

// Angle between w and the normal (0,0,1). acos(w.z) loses all precision near the normal;
// 2 asin(|w - n| / 2) does not (it is what the RGL reference readers use). Expects |w| = 1.
inline float elevation(const Vec3& w) {
    float d = std::sqrt(w.x * w.x + w.y * w.y + (w.z - 1.f) * (w.z - 1.f));
    const float half = 0.5f * d;
    return 2.f * std::asin(half < 1.f ? half : 1.f);
}

// Azimuth in (-pi, pi], 0 along the tangent x.
inline float azimuth(const Vec3& w) { return std::atan2(w.y, w.x); }

// Unit direction from spherical angles in the local frame (z normal, x tangent).
inline Vec3 spherical_direction(float theta, float phi) {
    float s = std::sin(theta);
    return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

constexpr float kPi = 3.14159265358979323846f;
constexpr double kPiD = 3.14159265358979323846;
// The D suffix as for kPiD: double, as the fit, the equation and the edits need. Both scalings
// are exact, so 0.5 * kPiD and kHalfPiD are the same double.
constexpr double kHalfPiD = 0.5 * kPiD, kTwoPiD = 2.0 * kPiD;

}  // namespace npf
