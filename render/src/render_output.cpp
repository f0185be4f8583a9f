#include <npf/render/render_output.h>

#include <npf/core/number_text.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/core/text.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <memory>

namespace npf::render {

namespace {

std::string wavelengths_text(const Channels& c) {
    if (c.is_rgb()) return "rgb";
    std::string s;
    for (float l : c.wavelengths()) s += (s.empty() ? "" : ",") + number_text(l);
    return s;
}

}  // namespace

RenderMetadata describe_render(const RenderResult& result, const RenderOptions& options,
                               const EnvironmentMap& environment) {
    const bool spectral = !result.channels.is_rgb();
    RenderMetadata m;
    m.emplace_back("npf:values",
                   std::string("scene-linear Rec.709 RGB (sRGB primaries, D65 white), alpha premultiplied; ") +
                       (spectral ? "rendered spectrally at the listed wavelengths, integrated against the CIE 1931 "
                                   "2-degree observer to XYZ (environment upsampled to D65-based illuminant spectra, "
                                   "RGB (1,1,1) = D65 at Y = 1), then to linear Rec.709"
                                 : "rendered in RGB (material and environment linear Rec.709)"));
    m.emplace_back("npf:scene", "sphere");
    m.emplace_back("npf:size", std::to_string(options.width) + "x" + std::to_string(options.height));
    m.emplace_back("npf:spp", std::to_string(options.spp));
    m.emplace_back("npf:seed", std::to_string(options.seed));
    m.emplace_back("npf:channels", wavelengths_text(result.channels));
    m.emplace_back("npf:sampling", options.sampling == Sampling::Mis    ? "mis (environment + BSDF, power heuristic)"
                                   : options.sampling == Sampling::Brdf ? "BSDF only"
                                                                        : "environment only");
    if (options.keep_negative) m.emplace_back("npf:negative_values", "kept (as Mitsuba's measured renders them)");
    m.emplace_back("npf:threads", std::to_string(result.stats.threads));
    m.emplace_back("npf:render_seconds", number_text(result.stats.seconds));
    m.emplace_back("npf:envmap", environment.source());
    m.emplace_back("npf:envmap_size", std::to_string(environment.width()) + "x" + std::to_string(environment.height()));
    m.emplace_back("npf:envmap_clamped_values", std::to_string(environment.clamped_values()));
    if (result.stats.dropped_values > 0)
        m.emplace_back("npf:dropped_values", std::to_string(result.stats.dropped_values));
    return m;
}

RenderMetadata describe_render(const RenderResult& result, const RenderOptions& options, const Lighting& lighting) {
    if (!lighting.directional()) {
        RenderMetadata m = describe_render(result, options, *lighting.map);
        m.emplace_back("npf:lighting", lighting.label());
        return m;
    }
    RenderOptions centres = options;
    centres.spp = 1;
    RenderMetadata m = describe_render(result, centres, EnvironmentMap::constant(0.f, 0.f, 0.f));
    // No map: its lines give way to the lights.
    m.erase(std::remove_if(m.begin(), m.end(), [](const auto& line) { return line.first.rfind("npf:envmap", 0) == 0; }),
            m.end());
    for (auto& [key, value] : m) {
        if (key == "npf:sampling")
            value = "none: directional lights evaluated at each pixel's centre (no Monte Carlo; two materials' renders differ "
                    "only by their BRDFs, with no noise floor)";
        if (key == "npf:seed") value = "unused";
    }
    std::string lights;
    for (const DirectionalLight& l : lighting.lights) {
        lights += (lights.empty() ? "" : "; ") + l.name + ": direction (" + number_text(l.direction.x) + ", " +
                  number_text(l.direction.y) + ", " + number_text(l.direction.z) + "), irradiance " + number_text(l.irradiance);
    }
    m.emplace_back("npf:lighting", lighting.label());
    m.emplace_back("npf:lights", lights);
    return m;
}

void write_render_exr(AtomicOutput& atomic, const RenderResult& result, const RenderMetadata& metadata) {
    const std::string& path = atomic.final_path();
    const color::FloatImage& img = result.image;
    if (img.channels != 4 || img.width == 0 || img.height == 0 ||
        img.pixels.size() != img.width * img.height * 4)
        throw Error(path, "not an RGBA render (size and pixel count disagree)");

    OIIO::ImageSpec spec(int(img.width), int(img.height), 4, OIIO::TypeFloat);
    spec.channelnames = {"R", "G", "B", "A"};
    spec.alpha_channel = 3;
    spec.attribute("compression", "zip");
    spec.attribute("oiio:ColorSpace", "Linear");
    // OpenEXR's chromaticities: Rec.709 primaries and the D65 white, x and y of R, G, B, W.
    const float chroma[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
    spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), chroma);
    spec.attribute("Software", "npf render");
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    localtime_r(&now, &tm);
    char date[32];
    std::strftime(date, sizeof date, "%Y:%m:%d %H:%M:%S", &tm);
    spec.attribute("DateTime", date);
    for (const auto& [name, value] : metadata)
        spec.attribute(name.find(':') == std::string::npos ? "npf:" + name : name, value);

    // OpenImageIO writes through the proxy into the temporary, never opening a file by name.
    // Declared before `out`, so that it outlives the writes `out` makes when destroyed unclosed.
    AtomicOutputProxy<OIIO::Filesystem::IOProxy> proxy(atomic);
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("openexr");
    if (!out) throw Error(path, "this build of OpenImageIO cannot write OpenEXR: " + first_line(OIIO::geterror()));
    if (!out->set_ioproxy(&proxy)) throw Error(path, "this build of OpenImageIO cannot write OpenEXR through a proxy");
    if (!out->open(atomic.temporary_path(), spec)) atomic.fail("cannot create output", first_line(out->geterror()));
    if (!out->write_image(OIIO::TypeFloat, img.pixels.data()))
        atomic.fail("cannot write the pixels", first_line(out->geterror()));
    if (!out->close()) atomic.fail("cannot finish output", first_line(out->geterror()));
}

void write_render_exr(const std::string& path, const RenderResult& result, const RenderMetadata& metadata) {
    AtomicOutput atomic(path);
    write_render_exr(atomic, result, metadata);
    atomic.commit();
}

}  // namespace npf::render
