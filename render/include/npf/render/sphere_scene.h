// The paper's Sphere scene: a unit sphere at the origin seen by a fixed pinhole camera, with a
// tangent field that makes anisotropic materials show their anisotropy.
//
// World space: right-handed, +y up (the environment map's orientation, environment_map.h).
//  - Camera: at (0, 0, 4), looking at the origin (down -z), +y up, +x to the right of the image.
//    The vertical field of view is chosen so that the sphere's silhouette spans 90 % of the
//    image height (tan(fov / 2) = tan(asin(1/4)) / 0.9, fov = 31.9 degrees); wider images see
//    more background on the sides. Raster coordinates: x from 0 (left) to width, y from 0 (top)
//    to height; pixel (i, j) covers [i, i + 1) x [j, j + 1).
//  - Shading frame at a point p of the sphere (n = p): the tangent t is the direction of
//    increasing longitude about the vertical axis, t = normalize(dp/dphi) = (z, 0, -x) / |(x, z)|,
//    horizontal and pointing to the right on the front of the sphere; the bitangent is
//    b = n x t (pointing "north", +y-ward); (t, b, n) is right-handed. At the poles, where
//    dp/dphi vanishes (|(x, z)| below 1e-6), t = (1, 0, 0) made orthogonal to n. The poles lie on
//    the silhouette as seen from this camera, so no visible pixel depends on that choice.
//  - The local frame of npf::Brdf: z = n, x = t, y = b. The camera-side direction (towards the
//    eye) is the Brdf's `wi`; the direction towards the light is `wo`.
#pragma once

#include <npf/core/vec.h>

#include <cstddef>

namespace npf::render {

struct Ray {
    Vec3 origin;
    Vec3 direction;  // unit
};

// An orthonormal frame; to_local gives the coordinates of a world vector in (t, b, n).
struct ShadingFrame {
    Vec3 t, b, n;
    Vec3 to_local(const Vec3& w) const { return {dot(w, t), dot(w, b), dot(w, n)}; }
    Vec3 to_world(const Vec3& l) const { return t * l.x + b * l.y + n * l.z; }
};

inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

struct SphereHit {
    float distance = 0.f;  // along the ray
    Vec3 position;         // on the unit sphere
    ShadingFrame frame;
};

class SphereScene {
public:
    // Camera distance from the sphere's centre and the fraction of the image height that the
    // silhouette spans.
    static constexpr float kCameraDistance = 4.f;
    static constexpr float kSilhouetteFraction = 0.9f;

    // An image of width x height pixels (both >= 1).
    SphereScene(std::size_t width, std::size_t height);

    std::size_t width() const { return m_width; }
    std::size_t height() const { return m_height; }

    // The camera ray through raster position (x, y).
    Ray camera_ray(float x, float y) const;

    // The first intersection of `ray` with the unit sphere in front of its origin, if any.
    // Numerically careful near the silhouette (the discriminant from the ray's distance to the
    // centre, Haines et al., Ray Tracing Gems ch. 7).
    static bool intersect(const Ray& ray, SphereHit& hit);

    // The shading frame at a point of the unit sphere (the tangent field above).
    static ShadingFrame frame_at(const Vec3& position);

    // tan(vertical fov / 2).
    float tan_half_fov() const { return m_tan_half_fov; }

private:
    std::size_t m_width, m_height;
    float m_tan_half_fov;
    Vec3 m_eye;
};

}  // namespace npf::render
