#include <npf/converter/psnr_prediction.h>

#include <npf/core/error.h>
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
    std::vector<render::Lighting> lightings;
    for (const std::string& name : m_options.lightings) lightings.push_back(render::make_lighting(name, "lighting"));
    render::PairedRenderSettings settings;
    settings.size = m_options.size;
    settings.spp = m_options.spp;
    settings.seed = m_options.seed;
    settings.threads = unsigned(m_options.threads > 0 ? m_options.threads : 0);
    settings.noise_floor = m_options.noise_floor;
    settings.reference_name = "source render";
    settings.test_name = "conversion render";
    for (render::Lighting& l : lightings) m_judged.emplace_back(source, std::move(l), settings);
}

PsnrPrediction PsnrPredictor::predict(const Brdf& conversion, bool with_floor) const {
    const auto start = Clock::now();
    PsnrPrediction p;
    p.psnr = std::numeric_limits<double>::infinity();
    for (const render::PairedReference& j : m_judged) {
        const render::PairedComparison c = j.compare(conversion, with_floor);
        LightingPrediction l;
        l.lighting = j.lighting().label();
        l.psnr = c.metrics.psnr;
        l.floor_psnr = c.floor_psnr;
        l.noise_limited = c.noise_limited;
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
    if (m_judged.size() == 1 && !m_judged[0].lighting().directional()) {
        const render::Lighting& l = m_judged[0].lighting();
        return "Sphere " + n + "x" + n + ", " + spp(l) + ", env sampling, " + seeds + ", " +
               std::filesystem::path(l.map->source()).filename().string();
    }
    std::string each;
    for (const render::PairedReference& j : m_judged) {
        each += (each.empty() ? "" : ", ") + j.lighting().label() + " " +
                (j.lighting().directional() ? std::string("at pixel centres (no noise)") : spp(j.lighting()));
    }
    return "Sphere " + n + "x" + n + ", env sampling, " + seeds + "; worst of " + each;
}

}  // namespace npf
