// The lightings a Sphere render can be lit by, by name: the one place that owns their names and
// geometry (docs/render.md sec. 2a). A conversion that looks right under one soft map can lose 5
// to 14 dB under a sharp light: the soft map averages away the height of glossy peaks and the
// grazing band, so conversions are judged under a set of lightings, each there for a reason:
//
//  - "studio": the shipped map (default_environment.h), soft and broad: the everyday look and
//    the paper's kind of comparison.
//  - "key-rim": a dim uniform sky with two small bright discs (3 degrees across), a key light
//    in front and a grazing rim light from behind: the key's reflection shows the height and
//    shape of a glossy peak, the rim the grazing band (large theta_d) along the silhouette, both
//    of which a soft map averages away. A procedural lat-long map, so the environment sampling
//    works unchanged.
//  - "directional": the key's and the rim's directions as delta lights, evaluated once at each
//    pixel centre with no Monte Carlo at all: pixel = sum over lights of E f_r cos(theta_o). Two
//    materials rendered so differ only by their BRDFs (no noise floor): a pointwise check.
//
// Geometry (world space as in sphere_scene.h: right-handed, +y up, the camera at (0, 0, 4)
// looking down -z, +x to the image's right). A light at elevation e above the horizon and
// azimuth a, measured from +z (towards the camera) towards +x, lies in the direction
//     (cos e sin a, sin e, cos e cos a).
// The key is at e = 35, a = +45 degrees (above, in front, to the camera's right); the rim at
// e = 10, a = -135 degrees (low, behind the sphere, to the camera's left), so it lights a crescent
// along the left silhouette. A user's map file is a lighting too (its path as the name).
#pragma once

#include <npf/core/brdf.h>
#include <npf/core/vec.h>
#include <npf/render/environment_map.h>
#include <npf/render/path_tracer.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace npf::render {

// The key-rim map's and the directional lights' numbers (radiances in the map's units: the
// shipped studio map's brightest texels are a few hundred, its mean about 1).
namespace key_rim {
constexpr double kSkyRadiance = 0.02;       // uniform, everywhere outside the discs
constexpr double kDiscDiameterDeg = 3.0;    // angular diameter of each disc
constexpr double kKeyRadiance = 400.0;
constexpr double kKeyElevationDeg = 35.0, kKeyAzimuthDeg = 45.0;
constexpr double kRimRadiance = 150.0;
constexpr double kRimElevationDeg = 10.0, kRimAzimuthDeg = -135.0;
// The procedural map's size: 0.18 degree texels, about 17 across a disc; texels the disc's edge
// crosses are supersampled (16 x 16) so the disc's power is right to a small fraction.
constexpr std::size_t kMapWidth = 2048, kMapHeight = 1024;

// Solid angle of one disc (sr): 2 pi (1 - cos(radius)).
double disc_solid_angle();
// The map's exact radiant power over the sphere, sum of radiance x solid angle (sr units):
// 4 pi sky + the discs' excess over the sky.
double total_power();
}  // namespace key_rim

// The unit direction of a light at `elevation_deg` above the horizon and `azimuth_deg` from +z
// towards +x (above).
Vec3 light_direction(double elevation_deg, double azimuth_deg);

// A delta light: irradiance `irradiance` (grey: the same in R, G and B, a flat spectrum) on a
// surface facing it, from `direction` (world space, unit, towards the light).
struct DirectionalLight {
    std::string name;
    Vec3 direction;
    double irradiance = 0.0;
};

struct Lighting {
    // "studio", "key-rim", "directional", or a map file's path.
    std::string name;
    // A map lighting's map (null for "directional"); shared, so that copies cost nothing.
    std::shared_ptr<const EnvironmentMap> map;
    std::vector<DirectionalLight> lights;  // "directional"
    // A paired prediction renders this lighting at spp x spp_factor (psnr_prediction.h): a
    // lighting whose paired noise floor is too close to the figures it judges carries more samples.
    std::uint32_t spp_factor = 1;

    bool directional() const { return !map; }
    // A short label for summaries and metadata keys: the name, or a map file's file name.
    std::string label() const;
};

// Lighting::label() of the lighting `name_or_map` names, without loading it.
std::string lighting_label(const std::string& name_or_map);

// The built-in names, in the default order of a prediction's set: studio, key-rim, directional.
const std::vector<std::string>& builtin_lighting_names();

// A built-in lighting by name, else the lat-long map file at `name_or_map`. Throws npf::Error
// naming `what` ("--light") when it is neither a name nor an existing file, and what
// EnvironmentMap::load throws for a file that is not a map.
Lighting make_lighting(const std::string& name_or_map, const std::string& what = "lighting");

// Checks a comma-separated list of lightings without loading any map: each item a built-in
// name or an existing file; none empty, none twice. Returns the items.
std::vector<std::string> parse_lighting_list(const std::string& text, const std::string& what);

// The key-rim map (above), at the given size.
EnvironmentMap key_rim_map(std::size_t width = key_rim::kMapWidth, std::size_t height = key_rim::kMapHeight);
// The directional lighting's lights: the key and the rim as delta lights, each with the
// irradiance of its key-rim disc (radiance x the disc's solid angle).
std::vector<DirectionalLight> directional_lights();

// Renders under any lighting: a map through render() (path_tracer.h), directional lights by
// render_directional.
RenderResult render(const Brdf& material, const Lighting& lighting, const RenderOptions& options,
                    const RenderProgress& progress = {});

// Delta lights, no Monte Carlo: one camera ray through each pixel's centre, pixel = sum over the
// lights above the local horizon of E f_r cos(theta_o) (the sphere is convex: nothing else
// shadows). options.spp, seed and sampling are not used; alpha is 1 where the centre ray hits.
// The colour is as render()'s: RGB, or the wavelength quadrature of a flat (grey) light.
RenderResult render_directional(const Brdf& material, const std::vector<DirectionalLight>& lights,
                                const RenderOptions& options, const RenderProgress& progress = {});

}  // namespace npf::render
