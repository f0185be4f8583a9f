#include <npf/render/lighting.h>

#include <npf/core/error.h>
#include <npf/core/parallel.h>
#include <npf/render/default_environment.h>
#include <npf/render/render_channels.h>
#include <npf/render/sphere_scene.h>

#include "row_tally.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <mutex>

namespace npf::render {

namespace {

constexpr double kDegree = kPiD / 180.0;

struct Vec3d {
    double x, y, z;
};

Vec3d direction_d(double elevation_deg, double azimuth_deg) {
    const double e = elevation_deg * kDegree, a = azimuth_deg * kDegree;
    return {std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a)};
}

// The lat-long direction (environment_map.h) of polar angle theta from +y and azimuth phi.
Vec3d latlong_d(double theta, double phi) {
    const double st = std::sin(theta);
    return {st * std::sin(phi), std::cos(theta), -st * std::cos(phi)};
}

// The angle between two unit vectors, accurate when small (2 asin(|a - b| / 2)).
double angle_between(const Vec3d& a, const Vec3d& b) {
    const double dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
    return 2.0 * std::asin(std::min(1.0, 0.5 * std::sqrt(dx * dx + dy * dy + dz * dz)));
}

double disc_radius() { return 0.5 * key_rim::kDiscDiameterDeg * kDegree; }

}  // namespace

double key_rim::disc_solid_angle() { return kTwoPiD * (1.0 - std::cos(disc_radius())); }

double key_rim::total_power() {
    return 4.0 * kPiD * kSkyRadiance + disc_solid_angle() * ((kKeyRadiance - kSkyRadiance) + (kRimRadiance - kSkyRadiance));
}

Vec3 light_direction(double elevation_deg, double azimuth_deg) {
    const Vec3d d = direction_d(elevation_deg, azimuth_deg);
    return {float(d.x), float(d.y), float(d.z)};
}

std::string lighting_label(const std::string& name_or_map) {
    const std::vector<std::string>& names = builtin_lighting_names();
    if (std::find(names.begin(), names.end(), name_or_map) != names.end()) return name_or_map;
    return std::filesystem::path(name_or_map).filename().string();
}

std::string Lighting::label() const { return lighting_label(name); }

const std::vector<std::string>& builtin_lighting_names() {
    static const std::vector<std::string> names = {"studio", "key-rim", "directional"};
    return names;
}

EnvironmentMap key_rim_map(std::size_t width, std::size_t height) {
    struct Disc {
        Vec3d centre;
        double theta;  // its polar angle from +y
        double radiance;
    };
    const Disc discs[2] = {
        {direction_d(key_rim::kKeyElevationDeg, key_rim::kKeyAzimuthDeg), kHalfPiD - key_rim::kKeyElevationDeg * kDegree,
         key_rim::kKeyRadiance},
        {direction_d(key_rim::kRimElevationDeg, key_rim::kRimAzimuthDeg), kHalfPiD - key_rim::kRimElevationDeg * kDegree,
         key_rim::kRimRadiance},
    };
    const double radius = disc_radius(), sky = key_rim::kSkyRadiance;
    const double d_theta = kPiD / double(height), d_phi = kTwoPiD / double(width);
    // A texel lies wholly inside or outside a disc when its centre is farther than this from the
    // disc's edge (half its diagonal, bounded with sin(theta) = 1).
    const double margin = 0.5 * std::sqrt(d_theta * d_theta + d_phi * d_phi);
    constexpr int kSub = 16;  // supersamples per side of a texel on a disc's edge

    std::vector<float> rgb(width * height * 3, float(sky));
    for (const Disc& disc : discs) {
        const double reach = radius + margin;
        const std::size_t first = std::size_t(std::max(0.0, std::floor((disc.theta - reach) / d_theta)));
        const std::size_t last = std::min(height - 1, std::size_t(std::ceil((disc.theta + reach) / d_theta)));
        for (std::size_t row = first; row <= last; ++row) {
            for (std::size_t col = 0; col < width; ++col) {
                const double theta = (double(row) + 0.5) * d_theta, phi = kTwoPiD * ((double(col) + 0.5) / double(width) - 0.5);
                const double distance = angle_between(latlong_d(theta, phi), disc.centre);
                if (distance > reach) continue;
                double covered = 1.0;
                if (distance > radius - margin) {
                    // The disc's share of the texel's solid angle (sin(theta)-weighted points).
                    double inside = 0.0, all = 0.0;
                    for (int i = 0; i < kSub; ++i) {
                        const double t = (double(row) + (i + 0.5) / kSub) * d_theta, w = std::sin(t);
                        for (int j = 0; j < kSub; ++j) {
                            const double p = kTwoPiD * ((double(col) + (j + 0.5) / kSub) / double(width) - 0.5);
                            all += w;
                            if (angle_between(latlong_d(t, p), disc.centre) <= radius) inside += w;
                        }
                    }
                    covered = inside / all;
                }
                float* texel = &rgb[(row * width + col) * 3];
                const float value = float(double(texel[0]) + covered * (disc.radiance - sky));
                texel[0] = texel[1] = texel[2] = value;
            }
        }
    }
    return EnvironmentMap(width, height, std::move(rgb), "key-rim");
}

std::vector<DirectionalLight> directional_lights() {
    const double omega = key_rim::disc_solid_angle();
    return {
        {"key", light_direction(key_rim::kKeyElevationDeg, key_rim::kKeyAzimuthDeg), key_rim::kKeyRadiance * omega},
        {"rim", light_direction(key_rim::kRimElevationDeg, key_rim::kRimAzimuthDeg), key_rim::kRimRadiance * omega},
    };
}

namespace {

bool is_builtin(const std::string& name) {
    const std::vector<std::string>& names = builtin_lighting_names();
    return std::find(names.begin(), names.end(), name) != names.end();
}

void check_lighting_item(const std::string& item, const std::string& what) {
    if (item.empty()) throw Error(what, "needs a lighting (studio, key-rim, directional) or an environment map file");
    if (is_builtin(item)) return;
    std::error_code ec;
    if (!std::filesystem::exists(item, ec))
        throw Error(what, "'" + item + "' is not a lighting (studio, key-rim, directional) nor an environment map file");
}

}  // namespace

std::vector<std::string> parse_lighting_list(const std::string& text, const std::string& what) {
    std::vector<std::string> items;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        check_lighting_item(item, what);
        if (std::find(items.begin(), items.end(), item) != items.end()) throw Error(what, "'" + item + "' is given twice");
        items.push_back(item);
        if (comma == std::string::npos) return items;
        start = comma + 1;
    }
}

Lighting make_lighting(const std::string& name_or_map, const std::string& what) {
    check_lighting_item(name_or_map, what);
    Lighting l;
    l.name = name_or_map;
    if (name_or_map == "studio") {
        l.map = std::make_shared<const EnvironmentMap>(EnvironmentMap::load(default_environment_map_path()));
    } else if (name_or_map == "key-rim") {
        // Made once per process (a fraction of a second) and shared by every render.
        static const std::shared_ptr<const EnvironmentMap> map = std::make_shared<const EnvironmentMap>(key_rim_map());
        l.map = map;
        // Twice the samples in a prediction: at 64 spp (128 x 128) ilm's paired floor was 47.4 dB
        // against a PSNR of 44.5 (noise-limited), and vch read 44.3 dB where 256 spp gives 45.8;
        // at 128 spp the floors were 50.3 and 52.6 dB, the PSNRs 45.1 and 45.5 (docs/metrics.md).
        l.spp_factor = 2;
    } else if (name_or_map == "directional") {
        l.lights = directional_lights();
    } else {
        l.map = std::make_shared<const EnvironmentMap>(EnvironmentMap::load(name_or_map));
    }
    return l;
}

RenderResult render(const Brdf& material, const Lighting& lighting, const RenderOptions& options, const RenderProgress& progress) {
    if (lighting.directional()) return render_directional(material, lighting.lights, options, progress);
    return render(material, *lighting.map, options, progress);
}

RenderResult render_directional(const Brdf& material, const std::vector<DirectionalLight>& lights, const RenderOptions& options,
                                const RenderProgress& progress) {
    const auto start = std::chrono::steady_clock::now();
    validate_render_options(options);
    const RenderChannels rc = choose_render_channels(material.info(), options.channels);
    ChannelQuery query = material.query(rc.channels);
    query.clamp_negative = !options.keep_negative;
    const std::size_t n = query.size();
    unsigned threads = unsigned(npf::thread_count(int(options.threads)));
    threads = unsigned(std::min<std::size_t>(threads, options.height));
    const SphereScene scene(options.width, options.height);
    const std::size_t width = options.width, height = options.height;

    RenderResult result = RenderResult::blank(rc.channels, width, height);
    RowTally tally(height, progress);

    npf::parallel_for(height, [&](std::size_t y) {
        std::vector<float> f(n);
        std::vector<double> acc(n);
        std::uint64_t row_hits = 0, row_dropped = 0;
        for (std::size_t x = 0; x < width; ++x) {
            const Ray ray = scene.camera_ray(float(x) + 0.5f, float(y) + 0.5f);
            SphereHit hit;
            if (!SphereScene::intersect(ray, hit)) continue;
            ++row_hits;
            float* out = &result.image.pixels[(y * width + x) * 4];
            out[3] = 1.f;
            const Vec3 wi = hit.frame.to_local(-ray.direction);
            if (!(wi.z > 0.f)) continue;  // grazing at the silhouette: black, as render()'s
            std::fill(acc.begin(), acc.end(), 0.0);
            for (const DirectionalLight& light : lights) {
                const Vec3 wo = hit.frame.to_local(light.direction);
                if (!(wo.z > 0.f)) continue;  // below the local horizon: the sphere itself shadows it
                material.eval_cos(wi, wo, query, f.data());
                for (std::size_t k = 0; k < n; ++k) {
                    const double c = light.irradiance * double(f[k]);
                    if (std::isfinite(c)) acc[k] += c;
                    else ++row_dropped;
                }
            }
            for (int c = 0; c < 3; ++c) {
                double v = 0.0;
                if (rc.spectral()) {
                    for (std::size_t k = 0; k < n; ++k) v += rc.to_rgb[std::size_t(c)][k] * acc[k];
                } else {
                    v = acc[std::size_t(c)];
                }
                out[c] = float(v);
            }
        }
        tally.add_row(row_hits, row_dropped);
    }, int(threads));
    const std::uint64_t hits = tally.hits, dropped = tally.dropped;

    result.stats.camera_samples = std::uint64_t(width) * height;
    result.stats.hit_samples = hits;
    result.stats.dropped_values = dropped;
    result.stats.threads = threads;
    result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (dropped > 0) {
        const std::string& path = material.info().path;
        throw Error(path.empty() ? material.info().format : path,
                    "the render has " + std::to_string(dropped) +
                        " non-finite contributions: the material gives values a render cannot hold");
    }
    return result;
}

}  // namespace npf::render
