// npf compare REF.exr TEST.exr: PSNR, SSIM, relMSE and MAPE of a test image against a reference
// (the paper's Tables 1 and 2), and optionally the relMSE heatmap (its Figs. 2, 5 and 7).
// Definitions: docs/metrics.md.
#include "command_line.h"
#include "commands.h"

#include <npf/color/display_image.h>
#include <npf/core/error.h>
#include <npf/core/json_text.h>
#include <npf/core/input_file.h>
#include <npf/render/heatmap.h>
#include <npf/render/image_metrics.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = {
    {"--heatmap", true, "also write the per-pixel relMSE as a PNG: blue 0, red 5 % and above, black not compared"},
    {"--heatmap-max", true, "relMSE shown red in the heatmap (default 0.05)"},
    {"--json", false, "print one JSON object instead of the lines"},
    {"--from", true, "what both images hold: linear (Rec.709 / sRGB primaries, default) or xyz (CIE XYZ D65)"},
    {"--all-pixels", false, "compare every pixel, also those with alpha 0 in both images"},
    {"--help", false, "show this help"},
};

const char* kHelp =
    "usage: npf compare REF.exr TEST.exr [--heatmap OUT.png] [--heatmap-max V] [--json] [--from linear|xyz]\n"
    "                   [--all-pixels]\n\n"
    "Compares a test image with a reference of the same size (any files OpenImageIO reads; the first\n"
    "three channels and alpha) and prints one metric per line:\n"
    "  PSNR          dB, on the display image (sRGB transfer, clamped to [0, 1], peak 1); inf if equal\n"
    "  SSIM          Wang et al. 2004 on the display image: 11 x 11 Gaussian window, sigma 1.5,\n"
    "                K1 0.01, K2 0.03; mean over R, G, B and the compared pixels where the window\n"
    "                fits (5 or more from every border; images of at least 11 x 11)\n"
    "  relMSE        mean of (t - r)^2 / (r^2 + 0.01) on the linear values\n"
    "  MAPE          mean of |t - r| / (|r| + 0.01) on the linear values, a fraction (x 100: percent)\n"
    "  pixels        pixels compared: with alpha, those with alpha > 0 in either image\n"
    "  pixels_total  width x height\n"
    "  ssim_pixels   compared pixels in the SSIM mean\n"
    "Definitions and choices: docs/metrics.md.\n\n";

// The shortest of %.9g that does not hide a difference from an exact 1 or 0 (an SSIM of
// 0.9999999996 must not print as 1).
std::string format_number(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    const double back = std::strtod(buf, nullptr);
    if (back != v && (back == 1.0 || back == 0.0)) std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

// JSON has no infinity: an infinite PSNR is the string "inf" (float("inf") in Python).
std::string json_number(double v) { return std::isfinite(v) ? format_number(v) : json_string(format_number(v)); }

double parse_heatmap_max(const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || !(v > 0.0))
        throw Error("--heatmap-max", "'" + text + "' is not a number > 0");
    return v;
}

color::FloatImage read_image(const std::string& path) {
    require_regular_file(path, "an image");
    return color::read_scene_image(path);
}

}  // namespace

int run_compare(const std::vector<std::string>& args) {
    CommandLine cl("compare", args, kFlags);
    if (cl.has("--help") || cl.positional().size() != 2) {
        std::printf("%s%s", kHelp, usage_lines(kFlags).c_str());
        return cl.has("--help") ? 0 : 2;
    }
    render::MetricOptions options;
    const std::string from = cl.value("--from", "linear");
    if (from == "linear") {
        options.input = color::SceneSpace::LinearRec709;
    } else if (from == "xyz") {
        options.input = color::SceneSpace::CieXyzD65;
    } else {
        throw Error("--from", "'" + from + "' is neither linear nor xyz");
    }
    options.coverage = cl.has("--all-pixels") ? render::Coverage::AllPixels : render::Coverage::Alpha;
    const double heatmap_max =
        cl.has("--heatmap-max") ? parse_heatmap_max(cl.value("--heatmap-max")) : render::kHeatmapMax;

    const std::string reference_path = cl.positional()[0], test_path = cl.positional()[1];
    const color::FloatImage reference = read_image(reference_path);
    const color::FloatImage test = read_image(test_path);
    const render::ImageMetrics m = render::compare_images(reference, test, options, reference_path, test_path);
    if (cl.has("--heatmap")) {
        const render::RelMseMap map = render::relmse_map(reference, test, options, reference_path, test_path);
        render::write_relmse_heatmap(cl.value("--heatmap"), map, heatmap_max);
    }

    if (cl.has("--json")) {
        std::printf("{\"reference\": %s, \"test\": %s, \"PSNR\": %s, \"SSIM\": %s, \"relMSE\": %s, \"MAPE\": %s, "
                    "\"pixels\": %zu, \"pixels_total\": %zu, \"ssim_pixels\": %zu, \"coverage\": \"%s\", "
                    "\"mse_display\": %s",
                    json_string(reference_path).c_str(), json_string(test_path).c_str(), json_number(m.psnr).c_str(),
                    json_number(m.ssim).c_str(), json_number(m.relmse).c_str(), json_number(m.mape).c_str(), m.pixels,
                    m.pixels_total, m.ssim_pixels, options.coverage == render::Coverage::Alpha ? "alpha" : "all",
                    json_number(m.mse_display).c_str());
        if (cl.has("--heatmap"))
            std::printf(", \"heatmap\": %s, \"heatmap_max\": %s", json_string(cl.value("--heatmap")).c_str(),
                        json_number(heatmap_max).c_str());
        std::printf("}\n");
    } else {
        std::printf("PSNR %s\nSSIM %s\nrelMSE %s\nMAPE %s\npixels %zu\npixels_total %zu\nssim_pixels %zu\n",
                    format_number(m.psnr).c_str(), format_number(m.ssim).c_str(), format_number(m.relmse).c_str(),
                    format_number(m.mape).c_str(), m.pixels, m.pixels_total, m.ssim_pixels);
    }
    return 0;
}

}  // namespace npf::cli
