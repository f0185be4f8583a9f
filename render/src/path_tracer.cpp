#include <npf/render/path_tracer.h>

#include <npf/core/error.h>
#include <npf/core/parallel.h>
#include <npf/render/environment_spectra.h>
#include <npf/render/render_channels.h>
#include <npf/render/rng.h>
#include <npf/render/sphere_scene.h>

#include "row_tally.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <vector>

namespace npf::render {

namespace {

// Dimension pairs of one camera sample (rng.h); fixed so that renders share random numbers.
constexpr std::uint32_t kDimPixel = 0, kDimEnvironment = 1, kDimBrdf = 2;

// Power heuristic weight of a strategy with density `a` against one with density `b`.
double power_heuristic(double a, double b) {
    if (!(a > 0.0)) return 0.0;
    if (!(b > 0.0)) return 1.0;
    const double r = b / a;
    return 1.0 / (1.0 + r * r);
}

// Radiance of the environment in the render's channels: RGB texels as they are, or the
// upsampled spectra at the quadrature nodes.
class EnvironmentRadiance {
public:
    EnvironmentRadiance(const EnvironmentMap& map, const RenderChannels& rc, unsigned threads) : m_map(map) {
        if (rc.spectral()) {
            m_spectra = std::make_unique<EnvironmentSpectra>(map, threads);
            const std::vector<float>& wl = rc.channels.wavelengths();
            // Only nodes with a colour weight are looked up (those far outside 360..830 nm have none).
            for (std::size_t k = 0; k < wl.size(); ++k) {
                if (rc.to_rgb[0][k] != 0.0 || rc.to_rgb[1][k] != 0.0 || rc.to_rgb[2][k] != 0.0) {
                    m_active.push_back(k);
                    m_wavelengths.push_back(double(wl[k]));
                }
            }
        }
    }
    // Writes the n values for `texel` (nodes without weight: 0); returns false when the texel is
    // black.
    bool eval(std::uint32_t texel, std::size_t n, float* out) const {
        const float* rgb = m_map.radiance(texel);
        if (!(rgb[0] > 0.f || rgb[1] > 0.f || rgb[2] > 0.f)) return false;
        if (m_spectra) {
            const color::RgbUnboundedSpectrum& s = m_spectra->spectrum(texel);
            for (std::size_t k = 0; k < n; ++k) out[k] = 0.f;
            for (std::size_t j = 0; j < m_active.size(); ++j) out[m_active[j]] = float(s(m_wavelengths[j]));
        } else {
            out[0] = rgb[0], out[1] = rgb[1], out[2] = rgb[2];
        }
        return true;
    }

private:
    const EnvironmentMap& m_map;
    std::unique_ptr<EnvironmentSpectra> m_spectra;
    std::vector<std::size_t> m_active;   // nodes with a non-zero colour weight
    std::vector<double> m_wavelengths;   // their wavelengths
};

}  // namespace

void validate_render_options(const RenderOptions& o) {
    const std::string src = "render options";
    const std::string side = "1.." + std::to_string(RenderOptions::kMaxSide);
    if (o.width < 1 || o.width > RenderOptions::kMaxSide) throw Error(src, "image width must be in " + side + ", got " + std::to_string(o.width));
    if (o.height < 1 || o.height > RenderOptions::kMaxSide)
        throw Error(src, "image height must be in " + side + ", got " + std::to_string(o.height));
    if (o.spp < 1 || o.spp > RenderOptions::kMaxSpp)
        throw Error(src, "samples per pixel must be in 1.." + std::to_string(RenderOptions::kMaxSpp) + ", got " + std::to_string(o.spp));
    if (o.threads > 1024) throw Error(src, "at most 1024 threads");
}

RenderResult render(const Brdf& material, const EnvironmentMap& environment, const RenderOptions& options,
                    const RenderProgress& progress) {
    const auto start = std::chrono::steady_clock::now();
    validate_render_options(options);

    const RenderChannels rc = choose_render_channels(material.info(), options.channels);
    ChannelQuery query = material.query(rc.channels);  // once per render, never per sample
    query.clamp_negative = !options.keep_negative;
    const std::size_t n = query.size();

    unsigned threads = unsigned(npf::thread_count(int(options.threads)));
    threads = unsigned(std::min<std::size_t>(threads, options.height));

    const EnvironmentRadiance radiance(environment, rc, threads);
    const SphereScene scene(options.width, options.height);
    const std::size_t width = options.width, height = options.height;
    const std::uint32_t spp = options.spp;
    const bool use_env = options.sampling != Sampling::Brdf, use_brdf = options.sampling != Sampling::Environment;

    RenderResult result = RenderResult::blank(rc.channels, width, height);

    RowTally tally(height, progress);

    // One item per row: each pixel is computed by one thread, into its own slot.
    npf::parallel_for(height, [&](std::size_t y) {
        std::vector<float> f(n), weight(n), env(n);
        std::vector<double> acc(n);
        std::uint64_t row_hits = 0, row_dropped = 0;
        for (std::size_t x = 0; x < width; ++x) {
            const std::uint64_t pixel = std::uint64_t(y) * width + x;
            const PixelSampler sampler(options.seed, pixel, spp);
            std::fill(acc.begin(), acc.end(), 0.0);
            std::uint32_t covered = 0;
            for (std::uint32_t s = 0; s < spp; ++s) {
                const Vec2 jitter = sampler.get_2d(s, kDimPixel);
                const Vec2 u_env = sampler.get_2d(s, kDimEnvironment);
                const Vec2 u_brdf = sampler.get_2d(s, kDimBrdf);
                const Ray ray = scene.camera_ray(float(x) + jitter.x, float(y) + jitter.y);
                SphereHit hit;
                if (!SphereScene::intersect(ray, hit)) continue;
                ++covered;
                const Vec3 wi = hit.frame.to_local(-ray.direction);
                if (!(wi.z > 0.f)) continue;  // grazing at the silhouette: black

                // Environment sample.
                EnvironmentSample es;
                if (use_env && environment.sample(u_env, es)) {
                    const Vec3 wo = hit.frame.to_local(es.direction);
                    if (wo.z > 0.f && radiance.eval(es.texel, n, env.data())) {
                        material.eval_cos(wi, wo, query, f.data());
                        const double mis = use_brdf ? power_heuristic(es.pdf, material.pdf(wi, wo)) : 1.0;
                        const double w = mis / double(es.pdf);
                        for (std::size_t k = 0; k < n; ++k) {
                            const double c = double(f[k]) * double(env[k]) * w;
                            if (std::isfinite(c)) acc[k] += c;
                            else ++row_dropped;
                        }
                    }
                }
                // BSDF sample.
                BrdfSample bs;
                if (use_brdf && material.sample(wi, u_brdf, query, bs, weight.data()) && bs.pdf > 0.f &&
                    bs.wo.z > 0.f) {
                    const Vec3 dir = normalize(hit.frame.to_world(bs.wo));
                    const std::uint32_t texel = environment.texel(dir);
                    if (radiance.eval(texel, n, env.data())) {
                        const double w = use_env ? power_heuristic(bs.pdf, environment.pdf(dir, texel)) : 1.0;
                        for (std::size_t k = 0; k < n; ++k) {
                            const double c = double(weight[k]) * double(env[k]) * w;
                            if (std::isfinite(c)) acc[k] += c;
                            else ++row_dropped;
                        }
                    }
                }
            }
            row_hits += covered;
            float* out = &result.image.pixels[pixel * 4];
            const double inv = 1.0 / double(spp);
            if (rc.spectral()) {
                for (int c = 0; c < 3; ++c) {
                    const std::vector<double>& w = rc.to_rgb[std::size_t(c)];
                    double v = 0.0;
                    for (std::size_t k = 0; k < n; ++k) v += w[k] * acc[k];
                    out[c] = float(v * inv);
                }
            } else {
                for (int c = 0; c < 3; ++c) out[c] = float(acc[std::size_t(c)] * inv);
            }
            out[3] = float(double(covered) * inv);
        }
        tally.add_row(row_hits, row_dropped);
    }, int(threads));
    const std::uint64_t hits = tally.hits, dropped = tally.dropped;

    result.stats.camera_samples = std::uint64_t(width) * height * spp;
    result.stats.hit_samples = hits;
    result.stats.dropped_values = dropped;
    result.stats.threads = threads;
    result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // A picture with holes or infinities is wrong, not approximate: it is refused, not written.
    // Readers bound what a material can produce (brdf.h), so this is a defect if it happens.
    std::size_t non_finite = 0;
    for (float v : result.image.pixels) non_finite += std::isfinite(v) ? 0 : 1;
    if (non_finite > 0 || dropped > 0) {
        const std::string& path = material.info().path;
        throw Error(path.empty() ? material.info().format : path,
                    "the render has " + std::to_string(dropped) + " non-finite contributions and " + std::to_string(non_finite) +
                        " non-finite pixel values: the material gives values a render cannot hold");
    }
    return result;
}

}  // namespace npf::render
