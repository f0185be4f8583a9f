#include <npf/converter/psnr_prediction.h>

#include <npf/render/default_environment.h>
#include <npf/render/image_metrics.h>
#include <npf/render/path_tracer.h>
#include <npf/shading/npf_brdf.h>

#include <chrono>
#include <filesystem>

namespace npf {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string environment_path(const PsnrPredictionOptions& o) {
    return o.environment.empty() ? render::default_environment_map_path() : o.environment;
}

}  // namespace

PsnrPredictor::PsnrPredictor(const Brdf& source, const PsnrPredictionOptions& options)
    : m_options(options), m_environment(render::EnvironmentMap::load(environment_path(options))) {
    const auto start = Clock::now();
    m_source = render_at(source, m_options.seed);
    if (m_options.floor_seed != 0) m_source_floor = render_at(source, m_options.floor_seed);
    m_source_seconds = seconds_since(start);
}

color::FloatImage PsnrPredictor::render_at(const Brdf& material, std::uint64_t seed) const {
    render::RenderOptions o;
    o.width = o.height = m_options.size;
    o.spp = m_options.spp;
    o.seed = seed;
    o.threads = unsigned(m_options.threads > 0 ? m_options.threads : 0);
    // Environment samples only: MIS would weigh each material's own BSDF samples, which differ
    // between the two, and the noise would no longer cancel in the difference.
    o.sampling = render::Sampling::Environment;
    return render::render(material, m_environment, o).image;
}

PsnrPrediction PsnrPredictor::predict(const Brdf& conversion, bool with_floor) const {
    const auto start = Clock::now();
    PsnrPrediction p;
    const color::FloatImage test = render_at(conversion, m_options.seed);
    const render::ImageMetrics m = render::compare_images(m_source, test, {}, "source render", "conversion render");
    p.psnr = m.psnr;
    if (with_floor && m_options.floor_seed != 0) {
        const color::FloatImage test2 = render_at(conversion, m_options.floor_seed);
        const render::NoiseFloor f = render::paired_noise_floor(m_source, test, m_source_floor, test2, {}, "source render",
                                                                "conversion render");
        p.floor_psnr = f.psnr;
        p.noise_limited = render::noise_limited(m, f);
    }
    p.seconds = seconds_since(start);
    return p;
}

PsnrPrediction PsnrPredictor::predict(const NpfModel& conversion, bool with_floor) const {
    return predict(NpfBrdf(conversion), with_floor);
}

std::string PsnrPredictor::settings_text() const {
    const std::string n = std::to_string(m_options.size);
    std::string text = "Sphere " + n + "x" + n + ", " + std::to_string(m_options.spp) + " spp, env sampling, seed " +
                       std::to_string(m_options.seed);
    if (m_options.floor_seed != 0) text += " (floor: seed " + std::to_string(m_options.floor_seed) + ")";
    return text + ", " + std::filesystem::path(m_environment.source()).filename().string();
}

}  // namespace npf
