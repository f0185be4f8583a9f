#include <npf/render/sphere_scene.h>

#include <algorithm>
#include <cmath>

namespace npf::render {

SphereScene::SphereScene(std::size_t width, std::size_t height)
    : m_width(std::max<std::size_t>(width, 1)), m_height(std::max<std::size_t>(height, 1)) {
    const double alpha = std::asin(1.0 / double(kCameraDistance));  // angular radius of the sphere
    m_tan_half_fov = float(std::tan(alpha) / double(kSilhouetteFraction));
    m_eye = {0.f, 0.f, kCameraDistance};
}

Ray SphereScene::camera_ray(float x, float y) const {
    // Normalised device coordinates scaled by the field of view; square pixels.
    const double aspect = double(m_width) / double(m_height);
    const double sx = (2.0 * double(x) / double(m_width) - 1.0) * aspect * m_tan_half_fov;
    const double sy = (1.0 - 2.0 * double(y) / double(m_height)) * m_tan_half_fov;
    const double len = std::sqrt(sx * sx + sy * sy + 1.0);
    return {m_eye, {float(sx / len), float(sy / len), float(-1.0 / len)}};
}

bool SphereScene::intersect(const Ray& ray, SphereHit& hit) {
    const double ox = ray.origin.x, oy = ray.origin.y, oz = ray.origin.z;
    const double dx = ray.direction.x, dy = ray.direction.y, dz = ray.direction.z;
    const double b = ox * dx + oy * dy + oz * dz;  // o.d (d unit)
    // The vector from the centre to the ray's closest point, o - (o.d) d: its length squared
    // gives the discriminant without the cancellation of b^2 - (o.o - 1).
    const double lx = ox - b * dx, ly = oy - b * dy, lz = oz - b * dz;
    const double disc = 1.0 - (lx * lx + ly * ly + lz * lz);
    if (disc < 0.0) return false;
    const double c = ox * ox + oy * oy + oz * oz - 1.0;
    const double q = -b + (b < 0.0 ? std::sqrt(disc) : -std::sqrt(disc));  // -b + sign(-b) sqrt
    double t0 = q != 0.0 ? c / q : 0.0, t1 = q;
    if (t0 > t1) std::swap(t0, t1);
    double t = t0 > 0.0 ? t0 : t1;
    if (!(t > 0.0)) return false;
    const double px = ox + t * dx, py = oy + t * dy, pz = oz + t * dz;
    const double len = std::sqrt(px * px + py * py + pz * pz);
    hit.distance = float(t);
    hit.position = {float(px / len), float(py / len), float(pz / len)};
    hit.frame = frame_at(hit.position);
    return true;
}

ShadingFrame SphereScene::frame_at(const Vec3& p) {
    ShadingFrame f;
    f.n = normalize(p);
    const double rx = f.n.x, rz = f.n.z;
    const double r = std::sqrt(rx * rx + rz * rz);
    Vec3 t;
    if (r > 1e-6) {
        t = {float(rz / r), 0.f, float(-rx / r)};
    } else {
        // At a pole: any horizontal direction, made orthogonal to n.
        const Vec3 x{1.f, 0.f, 0.f};
        t = normalize(x - f.n * dot(x, f.n));
    }
    f.t = t;
    f.b = normalize(cross(f.n, f.t));
    return f;
}

}  // namespace npf::render
