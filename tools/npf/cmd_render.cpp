// npf render MATERIAL -o OUT.exr: the paper's Sphere scene under an environment map, path-traced
// with multiple importance sampling; deterministic for a given seed (docs/render.md).
#include "command_line.h"

#include <npf/core/number_text.h>
#include "commands.h"
#include "file_uses.h"
#include "progress.h"

#include <npf/color/display.h>
#include <npf/color/display_image.h>
#include <npf/materials/open_material.h>
#include <npf/core/atomic_file.h>
#include <npf/core/channels.h>
#include <npf/core/error.h>
#include <npf/render/default_environment.h>
#include <npf/render/environment_map.h>
#include <npf/render/lighting.h>
#include <npf/render/path_tracer.h>
#include <npf/render/render_output.h>
#include <npf/render/render_settings.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <tuple>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = flag_table({
    "-o VALUE  output OpenEXR (float RGBA, scene-linear Rec.709, premultiplied alpha), required",
    "--light VALUE  studio (default: the shipped map), key-rim (a sky with a key and a grazing rim disc), directional (the "
    "key and rim as delta lights, no Monte Carlo) or a lat-long map file (docs/render.md)",
    "--env VALUE  lat-long HDR environment map (or a --light name)",
    "--png VALUE  also write a display-encoded 8-bit PNG through OpenColorIO",
    "--size VALUE  image size in pixels: N (square) or WxH (default 256)",
    "--spp VALUE  samples per pixel (default 64)",
    "--seed VALUE  random seed, a whole number >= 0 (default 0)",
    "--scene VALUE  scene: sphere (default; the only one)",
    "--threads VALUE  threads (default: all cores)",
    "--wavelengths VALUE  rgb, start:end:count or a,b,c nm (default: as the material stores)",
    "--sampling VALUE  mis (default), brdf or env: both strategies with MIS, or one alone (to check convergence)",
    "--exposure VALUE  stops applied to the PNG only (default 0; the EXR stays scene-linear)",
    "--raw  keep a measured file's negative (out-of-gamut) values, as Mitsuba's measured plugin does, instead of "
    "clamping them to 0 as the RGL loader does",
    "--quiet  no progress bar",
});

const char* kHelp =
    "usage: npf render MATERIAL -o OUT.exr [--light studio|key-rim|directional|MAP.exr] [--png OUT.png]\n"
    "                  [--size N|WxH] [--spp N]\n"
    "                  [--seed S] [--scene sphere] [--threads N] [--wavelengths LIST] [--exposure E]\n"
    "                  [--sampling mis|brdf|env] [--quiet]\n\n"
    "Renders the paper's Sphere scene: a unit sphere with a tangent field around its vertical axis,\n"
    "lit by a lat-long environment map (a named lighting or a file), with multiple importance sampling\n"
    "of the material and the map, or by directional lights without Monte Carlo. MATERIAL is an RGL .bsdf, MERL .binary, NPF texture .exr or analytic recipe .yaml. RGB\n"
    "materials render in RGB, spectral ones at a fixed wavelength quadrature, integrated to CIE XYZ\n"
    "and written as linear Rec.709. The image depends only on the material, the map, the options\n"
    "and the seed (not on --threads); the same seed gives different materials the same random\n"
    "numbers. docs/render.md has the conventions. Example:\n"
    "  npf render brushed_copper.yaml -o copper.exr --png copper.png --spp 256\n\n";

std::string describe_channels(const Channels& c) {
    if (c.is_rgb()) return "RGB";
    const std::vector<float>& w = c.wavelengths();
    char b[96];
    std::snprintf(b, sizeof b, "spectral, %zu wavelengths %g..%g nm", w.size(), double(w.front()), double(w.back()));
    return b;
}

}  // namespace

int run_render(const std::vector<std::string>& args) {
    const CommandLine cl = read_command_line(kHelp, kFlags, args);
    cl.expect_positional(1, 1, "one MATERIAL");
    cl.require("-o");
    const std::string material_path = cl.positional()[0], output = cl.value("-o");
    const std::string png = cl.value("--png");
    if (cl.has("--png") && png.empty()) throw Error("--png", "needs a file name");
    if (output.empty()) throw Error("-o", "needs a file name");

    // Every flag first, so that a typo fails before any work.
    render::RenderOptions options;
    // Each through its one declaration (render_settings.h), as a batch's render.* keys are.
    if (cl.has("--size")) std::tie(options.width, options.height) = render::parse_image_size(cl.value("--size"), "--size");
    options.spp = std::uint32_t(cl.whole("--spp", render::kSppSetting.min, render::kSppSetting.max, options.spp));
    options.seed = cl.whole("--seed", render::kSeedSetting.min, render::kSeedSetting.max, options.seed);
    options.threads = unsigned(cl.whole("--threads", render::kThreadsSetting.min, render::kThreadsSetting.max, options.threads));
    if (cl.has("--scene") && cl.value("--scene") != "sphere")
        throw Error("--scene", "'" + cl.value("--scene") + "' is not a known scene (sphere)");
    if (cl.has("--wavelengths")) options.channels = parse_channel_list(cl.value("--wavelengths"), "--wavelengths");
    if (cl.has("--sampling")) {
        const std::string v = cl.value("--sampling");
        if (v == "mis") options.sampling = render::Sampling::Mis;
        else if (v == "brdf") options.sampling = render::Sampling::Brdf;
        else if (v == "env") options.sampling = render::Sampling::Environment;
        else throw Error("--sampling", "'" + v + "' is not mis, brdf or env");
    }
    options.keep_negative = cl.has("--raw");
    const double exposure = cl.number("--exposure", 0.0);
    if (std::fabs(exposure) > 64.0) throw Error("--exposure", "must be within -64..64 stops");

    // A destination that cannot be written fails now, not after the render; nor may it replace an
    // input or the other output.
    FileUses uses;
    uses.input(material_path, "the material");
    if (cl.has("--env") && cl.has("--light")) throw Error("--light", "give --light or --env, not both");
    const std::string light_flag = cl.has("--env") ? "--env" : "--light";
    const std::string light = cl.value(light_flag, "studio");
    if (light.empty()) throw Error(light_flag, "needs a lighting name or a map file");
    const std::vector<std::string>& names = render::builtin_lighting_names();
    const bool named = std::find(names.begin(), names.end(), light) != names.end();
    if (!named) uses.input(light, light_flag);
    uses.output(output, "-o");
    if (!png.empty()) uses.output(png, "--png");
    uses.check();
    check_output_path(output);
    if (!png.empty()) check_output_path(png);

    const std::unique_ptr<Brdf> material = open_material(material_path);
    const render::Lighting lighting = render::make_lighting(light, light_flag);
    // The display transform before rendering: a missing or broken OCIO config fails fast.
    std::optional<color::DisplayTransform> display;
    if (!png.empty()) display.emplace(color::DisplayOptions{});

    ProgressBar bar("render " + output, !cl.has("--quiet"));
    const render::RenderResult result =
        render::render(*material, lighting, options, [&bar](double f) { bar.update(f); });
    bar.finish();

    render::RenderMetadata meta = render::describe_render(result, options, lighting);
    meta.insert(meta.begin(), {"npf:material", material_path});
    if (!material->info().description.empty()) meta.emplace_back("npf:material_description", material->info().description);
    // All or nothing: both files are written in full before either is published, so that a
    // failure (a full disk) leaves both earlier outputs as they were.
    AtomicOutput exr_out(output);
    render::write_render_exr(exr_out, result, meta);
    std::optional<AtomicOutput> png_out;
    if (display) {
        color::FloatImage shown = result.image;
        const float scale = float(std::exp2(exposure));
        if (scale != 1.f)
            for (std::size_t i = 0; i < shown.pixels.size(); i += 4)
                for (int c = 0; c < 3; ++c) shown.pixels[i + std::size_t(c)] *= scale;
        png_out.emplace(png);
        color::write_display_png(*png_out, shown, *display);
    }
    commit_together({&exr_out, png_out ? &*png_out : nullptr});

    const render::RenderStats& s = result.stats;
    // Directional lights: one ray per pixel centre, so no sample count and no noise to speak of.
    const std::string samples = lighting.directional() ? "pixel centres (no Monte Carlo, no noise floor)"
                                                       : std::to_string(options.spp) + " spp";
    std::printf("wrote %s%s%s: %zux%zu, %s, %s, under %s, %.2f s, %.2f M samples/s on %u thread%s\n", output.c_str(),
                png.empty() ? "" : " and ", png.c_str(), options.width, options.height, samples.c_str(),
                describe_channels(result.channels).c_str(), lighting.label().c_str(), s.seconds,
                s.seconds > 0.0 ? double(s.camera_samples) / s.seconds / 1e6 : 0.0, s.threads, s.threads == 1 ? "" : "s");
    return 0;
}

}  // namespace npf::cli
