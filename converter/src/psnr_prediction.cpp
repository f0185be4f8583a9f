#include <npf/converter/psnr_prediction.h>

#include <npf/core/error.h>
#include <npf/render/image_metrics.h>
#include <npf/render/path_tracer.h>
#include <npf/shading/npf_brdf.h>

#include <chrono>
#include <filesystem>
#include <limits>

namespace npf {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace

PsnrPredictor::PsnrPredictor(const Brdf& source, const PsnrPredictionOptions& options) : m_options(options) {
    if (m_options.lightings.empty()) throw Error("prediction", "needs at least one lighting");
    // Every lighting first: a missing map fails before any render.
    for (const std::string& name : m_options.lightings) m_judged.push_back({render::make_lighting(name, "lighting"), {}, {}});
    for (Judged& j : m_judged) {
        j.source = render_at(source, j.lighting, m_options.seed);
        if (m_options.noise_floor && !j.lighting.directional())
            j.source_floor = render_at(source, j.lighting, render::noise_floor_seed(m_options.seed));
    }
}

color::FloatImage PsnrPredictor::render_at(const Brdf& material, const render::Lighting& lighting, std::uint64_t seed) const {
    render::RenderOptions o;
    o.width = o.height = m_options.size;
    o.spp = m_options.spp * lighting.spp_factor;
    o.seed = seed;
    o.threads = unsigned(m_options.threads > 0 ? m_options.threads : 0);
    // Environment samples only: MIS would weigh each material's own BSDF samples, which differ
    // between the two, and the noise would no longer cancel in the difference.
    o.sampling = render::Sampling::Environment;
    return render::render(material, lighting, o).image;
}

PsnrPrediction PsnrPredictor::predict(const Brdf& conversion, bool with_floor) const {
    const auto start = Clock::now();
    PsnrPrediction p;
    p.psnr = std::numeric_limits<double>::infinity();
    for (const Judged& j : m_judged) {
        LightingPrediction l;
        l.lighting = j.lighting.label();
        const color::FloatImage test = render_at(conversion, j.lighting, m_options.seed);
        const render::ImageMetrics m = render::compare_images(j.source, test, {}, "source render", "conversion render");
        l.psnr = m.psnr;
        if (with_floor && m_options.noise_floor) {
            if (j.lighting.directional()) {
                l.floor_psnr = std::numeric_limits<double>::infinity();  // no samples, no noise
            } else {
                const color::FloatImage test2 = render_at(conversion, j.lighting, render::noise_floor_seed(m_options.seed));
                const render::NoiseFloor f = render::paired_noise_floor(j.source, test, j.source_floor, test2, {},
                                                                        "source render", "conversion render");
                l.floor_psnr = f.psnr;
                l.noise_limited = render::noise_limited(m, f);
            }
        }
        // The first of equal ones is the worst (an exact +infinity everywhere names the first).
        if (p.lightings.empty() || l.psnr < p.psnr) {
            p.psnr = l.psnr;
            p.floor_psnr = l.floor_psnr;
            p.noise_limited = l.noise_limited;
            p.worst = l.lighting;
        }
        p.lightings.push_back(l);
    }
    p.seconds = seconds_since(start);
    return p;
}

PsnrPrediction PsnrPredictor::predict(const NpfModel& conversion, bool with_floor) const {
    return predict(NpfBrdf(conversion), with_floor);
}

std::string PsnrPredictor::settings_text() const {
    const std::string n = std::to_string(m_options.size);
    const std::string seeds = "seed " + std::to_string(m_options.seed) +
                              (m_options.noise_floor ? " (floor: seed " + std::to_string(render::noise_floor_seed(m_options.seed)) + ")" : "");
    const auto spp = [&](const render::Lighting& l) { return std::to_string(m_options.spp * l.spp_factor) + " spp"; };
    // One map: the words of the single-map prediction, so that such a file reads as it did.
    if (m_judged.size() == 1 && !m_judged[0].lighting.directional()) {
        const render::Lighting& l = m_judged[0].lighting;
        return "Sphere " + n + "x" + n + ", " + spp(l) + ", env sampling, " + seeds + ", " +
               std::filesystem::path(l.map->source()).filename().string();
    }
    std::string each;
    for (const Judged& j : m_judged) {
        each += (each.empty() ? "" : ", ") + j.lighting.label() + " " +
                (j.lighting.directional() ? std::string("at pixel centres (no noise)") : spp(j.lighting));
    }
    return "Sphere " + n + "x" + n + ", env sampling, " + seeds + "; worst of " + each;
}

}  // namespace npf
