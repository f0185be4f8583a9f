#include <npf/render/paired_render.h>

#include <limits>
#include <utility>

namespace npf::render {

RenderOptions paired_render_options(const PairedRenderSettings& settings, const Lighting& lighting, std::uint64_t seed) {
    RenderOptions o;
    o.width = o.height = settings.size;
    o.spp = settings.spp * lighting.spp_factor;  // more where the floor is near the figures it judges
    o.seed = seed;
    o.threads = settings.threads;
    // Environment samples only: MIS would weigh each material's own BSDF samples, which differ
    // between the two, and the noise would no longer cancel in the difference.
    o.sampling = Sampling::Environment;
    return o;
}

PairedReference::PairedReference(const Brdf& reference, Lighting lighting, PairedRenderSettings settings)
    : m_lighting(std::move(lighting)), m_settings(std::move(settings)) {
    m_reference = render(reference, m_lighting, options());
    if (m_settings.noise_floor && !m_lighting.directional())
        m_reference_floor = render(reference, m_lighting, paired_render_options(m_settings, m_lighting, noise_floor_seed(m_settings.seed)));
}

PairedComparison PairedReference::compare(const Brdf& test, bool with_floor) const {
    PairedComparison c;
    c.test = render(test, m_lighting, options());
    c.metrics = compare_images(m_reference.image, c.test.image, {}, m_settings.reference_name, m_settings.test_name);
    if (!with_floor || !m_settings.noise_floor) return c;
    if (m_lighting.directional()) {
        c.floor_psnr = std::numeric_limits<double>::infinity();  // no samples, no noise
        return c;
    }
    const RenderResult test2 = render(test, m_lighting, paired_render_options(m_settings, m_lighting, noise_floor_seed(m_settings.seed)));
    const NoiseFloor floor = paired_noise_floor(m_reference.image, c.test.image, m_reference_floor->image, test2.image, {},
                                                m_settings.reference_name, m_settings.test_name);
    c.floor_psnr = floor.psnr;
    c.noise_limited = noise_limited(c.metrics, floor);
    return c;
}

}  // namespace npf::render
