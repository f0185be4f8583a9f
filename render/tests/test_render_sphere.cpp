// The Sphere scene's geometry (npf/render/sphere_scene.h): the camera, ray-sphere intersection
// at the centre and the silhouette, and the tangent field (orthonormal, right-handed, tangent
// along the longitude, robust at the poles).
#include <npf/render/sphere_scene.h>

#include <gtest/gtest.h>

#include <cmath>

namespace {

using npf::Vec3;
using npf::render::Ray;
using npf::render::ShadingFrame;
using npf::render::SphereHit;
using npf::render::SphereScene;

void expect_orthonormal(const ShadingFrame& f, const char* what) {
    EXPECT_NEAR(npf::length(f.t), 1.f, 1e-6f) << what;
    EXPECT_NEAR(npf::length(f.b), 1.f, 1e-6f) << what;
    EXPECT_NEAR(npf::length(f.n), 1.f, 1e-6f) << what;
    EXPECT_NEAR(npf::dot(f.t, f.b), 0.f, 1e-6f) << what;
    EXPECT_NEAR(npf::dot(f.t, f.n), 0.f, 1e-6f) << what;
    EXPECT_NEAR(npf::dot(f.b, f.n), 0.f, 1e-6f) << what;
    // Right-handed: t x b = n.
    const Vec3 c = npf::render::cross(f.t, f.b);
    EXPECT_NEAR(c.x, f.n.x, 1e-6f) << what;
    EXPECT_NEAR(c.y, f.n.y, 1e-6f) << what;
    EXPECT_NEAR(c.z, f.n.z, 1e-6f) << what;
}

TEST(RenderSphere, CentreRayHitsTheFrontOfTheSphere) {
    const SphereScene scene(64, 64);
    const Ray r = scene.camera_ray(32.f, 32.f);
    EXPECT_FLOAT_EQ(r.origin.z, 4.f);
    EXPECT_NEAR(r.direction.z, -1.f, 1e-7f);
    SphereHit hit;
    ASSERT_TRUE(SphereScene::intersect(r, hit));
    EXPECT_NEAR(hit.distance, 3.f, 1e-6f);
    EXPECT_NEAR(hit.position.z, 1.f, 1e-6f);
    // The tangent points right (+x), the bitangent up (+y), the normal at the camera.
    EXPECT_NEAR(hit.frame.t.x, 1.f, 1e-6f);
    EXPECT_NEAR(hit.frame.b.y, 1.f, 1e-6f);
    EXPECT_NEAR(hit.frame.n.z, 1.f, 1e-6f);
    // Towards the camera is the Brdf's wi: straight along the normal here.
    const Vec3 wi = hit.frame.to_local(-r.direction);
    EXPECT_NEAR(wi.z, 1.f, 1e-6f);
}

TEST(RenderSphere, SilhouetteSpansNinetyPercentOfTheHeight) {
    const std::size_t h = 1000;
    const SphereScene scene(h, h);
    // Walk down the centre column: the first and last rows that hit.
    int first = -1, last = -1;
    for (int y = 0; y < int(h); ++y) {
        SphereHit hit;
        if (SphereScene::intersect(scene.camera_ray(500.f, float(y) + 0.5f), hit)) {
            if (first < 0) first = y;
            last = y;
        }
    }
    ASSERT_GE(first, 0);
    EXPECT_NEAR(double(last - first + 1) / double(h), 0.9, 0.003);
    // Up in the image is +y in the world: the top of the silhouette, where the view rays graze
    // the sphere, lies on the circle z = 1/4, y = sqrt(15) / 4 = 0.968.
    SphereHit top;
    ASSERT_TRUE(SphereScene::intersect(scene.camera_ray(500.f, float(first) + 0.5f), top));
    EXPECT_NEAR(top.position.y, 0.968f, 0.02f);
    // Right in the image is +x.
    SphereHit right;
    ASSERT_TRUE(SphereScene::intersect(scene.camera_ray(900.f, 500.f), right));
    EXPECT_GT(right.position.x, 0.5f);
    // A wider image keeps the vertical extent and shows more on the sides.
    const SphereScene wide(200, 100);
    EXPECT_FLOAT_EQ(wide.tan_half_fov(), scene.tan_half_fov());
    SphereHit miss;
    EXPECT_FALSE(SphereScene::intersect(wide.camera_ray(5.f, 50.f), miss));
}

TEST(RenderSphere, GrazingRaysAreAccurate) {
    // Rays passing the centre at distance d: a hit exactly when d <= 1, and the hit point on
    // the unit sphere with the normal nearly perpendicular to the ray at the rim.
    for (double d : {0.0, 0.5, 0.99, 0.999999, 1.000001, 1.1}) {
        const Ray r{{float(d), 0.f, 4.f}, {0.f, 0.f, -1.f}};
        SphereHit hit;
        const bool h = SphereScene::intersect(r, hit);
        EXPECT_EQ(h, d <= 1.0) << d;
        if (h) {
            EXPECT_NEAR(npf::length(hit.position), 1.f, 1e-6f);
            EXPECT_NEAR(hit.position.x, float(d), 1e-6f);
            EXPECT_GE(hit.position.z, 0.f);
        }
    }
    // A ray starting inside exits; a ray pointing away misses.
    SphereHit hit;
    EXPECT_TRUE(SphereScene::intersect({{0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}}, hit));
    EXPECT_NEAR(hit.position.y, 1.f, 1e-6f);
    EXPECT_FALSE(SphereScene::intersect({{0.f, 0.f, 4.f}, {0.f, 0.f, 1.f}}, hit));
}

TEST(RenderSphere, TangentFieldRunsAlongTheLongitude) {
    const double pi = 3.14159265358979323846;
    for (int i = 0; i <= 40; ++i) {
        for (int j = 0; j < 16; ++j) {
            const double theta = pi * i / 40.0, phi = 2.0 * pi * j / 16.0;
            const Vec3 p{float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)), float(std::sin(theta) * std::sin(phi))};
            const ShadingFrame f = SphereScene::frame_at(p);
            expect_orthonormal(f, "frame");
            EXPECT_NEAR(f.t.y, 0.f, 1e-6f);  // horizontal: along a parallel
            if (i > 0 && i < 40) {
                // dp/dphi about +y for p = (x, y, z) is proportional to (z, 0, -x).
                const double r = std::hypot(double(p.x), double(p.z));
                EXPECT_NEAR(f.t.x, p.z / r, 1e-5);
                EXPECT_NEAR(f.t.z, -p.x / r, 1e-5);
                EXPECT_GT(f.b.y, 0.f);  // the bitangent points north
            }
        }
    }
    // Exactly at the poles and next to them: still a valid frame.
    for (const Vec3& p : {Vec3{0.f, 1.f, 0.f}, Vec3{0.f, -1.f, 0.f}, Vec3{1e-8f, 1.f, 0.f}, Vec3{0.f, 1.f, -1e-7f}}) {
        const ShadingFrame f = SphereScene::frame_at(p);
        expect_orthonormal(f, "pole");
        EXPECT_TRUE(std::isfinite(f.t.x) && std::isfinite(f.b.z));
    }
    // to_world inverts to_local.
    const ShadingFrame f = SphereScene::frame_at(Vec3{0.36f, 0.48f, 0.8f});
    const Vec3 w{0.2f, -0.3f, 0.932738f};
    const Vec3 back = f.to_world(f.to_local(w));
    EXPECT_NEAR(back.x, w.x, 1e-6f);
    EXPECT_NEAR(back.y, w.y, 1e-6f);
    EXPECT_NEAR(back.z, w.z, 1e-6f);
}

}  // namespace
