// A lat-long (equirectangular) HDR environment map: the only light of the Sphere scene. Loading,
// radiance lookup, importance sampling and its exact solid-angle density.
//
// Orientation (fixed; docs/render.md): world space is right-handed with +y up; the camera of
// the Sphere scene looks down -z. Texel rows run from +y (row 0, the top of the image, v = 0)
// to -y (the last row, v = 1); the polar angle from +y is theta = pi v. Columns run with the
// azimuth phi = 2 pi (u - 1/2) measured from -z towards +x:
//     direction(u, v) = (sin theta sin phi, cos theta, -sin theta cos phi)
// so the centre of the image (u = 1/2) lies straight ahead of the camera (-z), u = 3/4 to its
// right (+x), u = 1/4 to its left (-x), and the left and right edges (u = 0 and 1) behind it
// (+z), which is what the front of the sphere reflects. This is the usual "panorama seen from
// inside" convention (Mitsuba 3's envmap with the image turned by half a turn about +y; a
// camera looking at the map's centre sees it unmirrored). Any width and height are accepted
// (2:1 is usual); texels are square in (u, v), not necessarily in solid angle.
//
// Radiance is piecewise constant: a direction takes the value of the texel it falls in (no
// filtering), the same cells the sampling distribution uses, so that radiance / density is
// constant within a texel row up to sin(theta).
//
// Sampling: texel (i, j) is drawn with probability proportional to luminance(i, j) sin(theta_i)
// (theta_i at the row centre; Rec.709 luminance of the RGB value), uniformly in (u, v) within the
// texel (PiecewiseConstant2D). The solid-angle density of a direction is then exactly
//     pdf(direction) = p_uv(texel) / (2 pi^2 sin theta),
// theta that of the direction itself (the Jacobian of (u, v) -> direction). A map that is black
// everywhere is sampled uniformly in solid angle instead (nothing is lost: it lights nothing).
//
// Values: linear RGB (Rec.709 primaries, taken as such whatever the file says) in radiance
// units. Non-finite values (NaN, infinity) are rejected with an npf::Error naming the file and
// the texel. Negative values are clamped to 0 and counted (clamped_values()): lossy-compressed
// HDR files (DWA, as the shipped studio.exr) carry tiny negative values around 1e-6 that are
// not light.
#pragma once

#include <npf/core/vec.h>
#include <npf/render/piecewise_constant_2d.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace npf::render {

// The lat-long mapping above: (u, v) in [0, 1]^2 <-> unit direction.
Vec3 latlong_direction(const Vec2& uv);
Vec2 latlong_coordinates(const Vec3& direction);  // u in [0, 1], v in [0, 1]

struct EnvironmentSample {
    Vec3 direction;           // world space, unit
    float pdf = 0.f;          // solid-angle density
    std::uint32_t texel = 0;  // index (row * width + column) of its radiance
};

class EnvironmentMap {
public:
    // Reads the first image of a file OpenImageIO reads (OpenEXR, Radiance .hdr, ...): its R,
    // G, B channels (by name, else the first three), or one channel as grey. Throws npf::Error
    // naming `path`: missing or unreadable file, 2 channels, a non-finite texel (and which).
    static EnvironmentMap load(const std::string& path);

    // From packed RGB floats, rows top (+y) to bottom, `source` naming it in messages and
    // metadata. Same checks and clamping as load().
    EnvironmentMap(std::size_t width, std::size_t height, std::vector<float> rgb, std::string source);
    // A map of one texel: the same radiance from every direction.
    static EnvironmentMap constant(float r, float g, float b);

    std::size_t width() const { return m_width; }
    std::size_t height() const { return m_height; }
    const std::string& source() const { return m_source; }
    // How many negative channel values were clamped to 0 on loading.
    std::size_t clamped_values() const { return m_clamped; }
    // Packed RGB, width * height * 3 floats, after clamping.
    const std::vector<float>& pixels() const { return m_rgb; }

    // The texel a direction falls in, and its radiance.
    std::uint32_t texel(const Vec3& direction) const;
    const float* radiance(std::uint32_t texel) const { return &m_rgb[std::size_t(texel) * 3]; }

    // Draws a direction from a uniform point in [0, 1)^2. Returns false (a zero-density sample,
    // at a pole) with probability 0 in exact arithmetic.
    bool sample(const Vec2& rnd, EnvironmentSample& s) const;
    // The solid-angle density with which sample() draws `direction` (unit, world space).
    float pdf(const Vec3& direction) const;
    // The same for a direction already known to lie in `texel`.
    float pdf(const Vec3& direction, std::uint32_t texel) const;

private:
    void build_distribution();

    std::size_t m_width = 0, m_height = 0;
    std::vector<float> m_rgb;
    std::string m_source;
    std::size_t m_clamped = 0;
    PiecewiseConstant2D m_distribution;
};

}  // namespace npf::render
