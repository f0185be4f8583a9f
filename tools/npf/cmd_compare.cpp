// npf compare REF.exr TEST.exr: PSNR, SSIM, relMSE and MAPE of a test image against a reference
// (the paper's Tables 1 and 2), optionally the relMSE heatmap (its Figs. 2, 5 and 7) and, from
// the pair rendered at a second seed (--floor), the PSNR's noise floor. Definitions:
// docs/metrics.md.
#include "command_line.h"

#include <npf/core/number_text.h>
#include "commands.h"
#include "file_uses.h"
#include "scene_space_flag.h"

#include <npf/color/display_image.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/core/json_text.h>
#include <npf/core/input_file.h>
#include <npf/render/heatmap.h>
#include <npf/render/image_metrics.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = flag_table({
    "--heatmap VALUE  also write the per-pixel relMSE as a PNG: blue 0, red 5 % and above, black not compared",
    "--heatmap-max VALUE  relMSE shown red in the heatmap (default 0.05)",
    "--json  print one JSON object instead of the lines",
    "--from VALUE  what both images hold: linear (Rec.709 / sRGB primaries, default) or xyz (CIE XYZ D65)",
    "--all-pixels  compare every pixel, also those with alpha 0 in both images",
    "--floor VALUE  REF2.exr [TEST2.exr]: the pair (or the reference alone) at a second seed: the PSNR's "
    "noise floor",
});

const char* kHelp =
    "usage: npf compare REF.exr TEST.exr [--floor REF2.exr [TEST2.exr]] [--heatmap OUT.png] [--heatmap-max V]\n"
    "                   [--json] [--from linear|xyz] [--all-pixels]\n\n"
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
    "With --floor REF2.exr TEST2.exr (the same two materials rendered at a second seed), also:\n"
    "  noise_floor_db    the PSNR of the seed noise alone: mean((e1 - e2)^2) / 2 with e the display\n"
    "                    error TEST - REF at each seed; a PSNR near it measures noise, not materials\n"
    "  noise_floor_kind  paired; with --floor REF2.exr alone, reference: the PSNR of REF against REF2\n"
    "  noise_limited     yes when the PSNR is within 3 dB of the floor (half or more of its MSE is noise)\n"
    "Render the pairs with `npf render --sampling env` at the same seed for a floor far above the\n"
    "PSNR (docs/metrics.md). Definitions and choices: docs/metrics.md.\n\n";

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

// A metric in the JSON report. Not npf::json_number: identical images have an infinite PSNR, a
// result that null ("no value") would hide, so it is the string "inf" (float("inf") in Python;
// docs/metrics.md); and SSIM keeps the digits that tell it from 1.
std::string metric_json(double v) { return std::isfinite(v) ? format_number(v) : json_string(format_number(v)); }

double parse_heatmap_max(const std::string& text) {
    const double v = parse_finite_number(text, "--heatmap-max");
    if (!(v > 0.0)) throw Error("--heatmap-max", "'" + text + "' is not a number > 0");
    return v;
}

color::FloatImage read_image(const std::string& path) {
    require_regular_file(path, "an image");
    return color::read_scene_image(path);
}

bool is_option(const std::string& a) {
    return a.size() >= 2 && a[0] == '-' && (a[1] == '-' || std::isalpha(static_cast<unsigned char>(a[1])));
}

// --floor takes one or two images, CommandLine's flags one value: it is taken out of the
// arguments here, with the one or two non-option arguments right after it (or its "=" value
// and at most one more).
struct FloorArguments {
    std::vector<std::string> rest;    // the arguments without --floor and its images
    std::vector<std::string> images;  // none: no --floor
};

FloorArguments take_floor_images(const std::vector<std::string>& args) {
    FloorArguments out;
    bool seen = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--") {  // the end of the options: the rest are images for CommandLine
            out.rest.insert(out.rest.end(), args.begin() + std::ptrdiff_t(i), args.end());
            break;
        }
        const bool bare = a == "--floor", inline_value = a.rfind("--floor=", 0) == 0;
        if (!bare && !inline_value) {
            out.rest.push_back(a);
            continue;
        }
        if (seen) throw Error("--floor", "given twice");
        seen = true;
        if (inline_value) out.images.push_back(a.substr(8));
        while (out.images.size() < 2 && i + 1 < args.size() && !is_option(args[i + 1])) out.images.push_back(args[++i]);
        if (out.images.empty() || out.images.front().empty())
            throw Error("--floor", "needs one or two images: REF2.exr [TEST2.exr], the reference (and the test) "
                                   "rendered at a second seed");
    }
    return out;
}

// What npf compare found, for printing.
struct CompareResult {
    std::string reference_path, test_path;
    std::optional<std::string> heatmap;  // the relMSE heatmap written, if any
    double heatmap_max;
    std::vector<std::string> floor_images;
    render::Coverage coverage;
    render::ImageMetrics metrics;
    std::optional<render::NoiseFloor> floor;
};

// --json: one object with the metrics, the heatmap's file and the floor.
void print_json(const CompareResult& c) {
    const render::ImageMetrics& m = c.metrics;
    const std::optional<render::NoiseFloor>& floor = c.floor;
    std::printf("{\"reference\": %s, \"test\": %s, \"PSNR\": %s, \"SSIM\": %s, \"relMSE\": %s, \"MAPE\": %s, "
                "\"pixels\": %zu, \"pixels_total\": %zu, \"ssim_pixels\": %zu, \"coverage\": \"%s\", "
                "\"mse_display\": %s",
                json_string(c.reference_path).c_str(), json_string(c.test_path).c_str(), metric_json(m.psnr).c_str(),
                metric_json(m.ssim).c_str(), metric_json(m.relmse).c_str(), metric_json(m.mape).c_str(), m.pixels,
                m.pixels_total, m.ssim_pixels, c.coverage == render::Coverage::Alpha ? "alpha" : "all",
                metric_json(m.mse_display).c_str());
    if (c.heatmap)
        std::printf(", \"heatmap\": %s, \"heatmap_max\": %s", json_string(*c.heatmap).c_str(),
                    metric_json(c.heatmap_max).c_str());
    if (floor) {
        std::printf(", \"noise_floor_db\": %s, \"noise_floor_kind\": \"%s\", \"mse_display_noise\": %s, "
                    "\"noise_limited\": %s, \"floor_reference\": %s",
                    metric_json(floor->psnr).c_str(), render::noise_floor_kind_name(floor->kind),
                    metric_json(floor->mse_noise).c_str(), render::noise_limited(m, *floor) ? "true" : "false",
                    json_string(c.floor_images[0]).c_str());
        if (c.floor_images.size() == 2)
            std::printf(", \"floor_test\": %s", json_string(c.floor_images[1]).c_str());
    }
    std::printf("}\n");
}

// One metric per line, then the floor and, for a reader, what the gap between them means.
void print_text(const CompareResult& c) {
    const render::ImageMetrics& m = c.metrics;
    const std::optional<render::NoiseFloor>& floor = c.floor;
    std::printf("PSNR %s\nSSIM %s\nrelMSE %s\nMAPE %s\npixels %zu\npixels_total %zu\nssim_pixels %zu\n",
                format_number(m.psnr).c_str(), format_number(m.ssim).c_str(), format_number(m.relmse).c_str(),
                format_number(m.mape).c_str(), m.pixels, m.pixels_total, m.ssim_pixels);
    if (floor) {
        const bool limited = render::noise_limited(m, *floor);
        std::printf("noise_floor_db %s\nnoise_floor_kind %s\nnoise_limited %s\n",
                    format_number(floor->psnr).c_str(), render::noise_floor_kind_name(floor->kind),
                    limited ? "yes" : "no");
        // For a reader: the PSNR beside its floor, and what follows from the gap.
        std::string verdict = "the PSNR measures the materials' difference (less than half of its error is seed "
                              "noise)";
        if (limited) {
            verdict = std::string(m.psnr >= floor->psnr ? "at or above the floor"
                                                         : "less than 3 dB below the floor") +
                      ", so at least half of the measured error is seed noise; the PSNR measures the renders' "
                      "noise, not the materials";
            // The reference floor assumes independent noise; a same-seed pair has less.
            if (floor->kind == render::NoiseFloorKind::Reference)
                verdict += " (if TEST was rendered at REF's seed, the paired floor, --floor REF2.exr TEST2.exr, "
                           "sees less noise)";
        }
        std::printf("summary: PSNR %.2f dB, noise floor %.2f dB (%s): %s\n", m.psnr, floor->psnr,
                    render::noise_floor_kind_name(floor->kind), verdict.c_str());
    }
}

}  // namespace

int run_compare(const std::vector<std::string>& args) {
    const FloorArguments floor_args = take_floor_images(args);
    const CommandLine cl = read_command_line(kHelp, kFlags, floor_args.rest);
    if (!floor_args.images.empty() && cl.positional().size() == 1)
        throw Error("--floor", "takes the one or two images right after it; give REF.exr TEST.exr before --floor");
    cl.expect_positional(2, 2, "two images REF.exr TEST.exr");
    render::MetricOptions options;
    options.input = scene_space_flag(cl);
    options.coverage = cl.has("--all-pixels") ? render::Coverage::AllPixels : render::Coverage::Alpha;
    const double heatmap_max =
        cl.has("--heatmap-max") ? parse_heatmap_max(cl.value("--heatmap-max")) : render::kHeatmapMax;

    const std::string reference_path = cl.positional()[0], test_path = cl.positional()[1];
    if (cl.has("--heatmap")) {
        FileUses uses;
        uses.input(reference_path, "REF").input(test_path, "TEST");
        for (const std::string& f : floor_args.images) uses.input(f, "--floor");
        uses.output(cl.value("--heatmap"), "--heatmap").check();
        check_output_path(cl.value("--heatmap"));  // before the images are read
    }
    const color::FloatImage reference = read_image(reference_path);
    const color::FloatImage test = read_image(test_path);
    const render::ImageMetrics m = render::compare_images(reference, test, options, reference_path, test_path);
    // The floor's images are read and checked before anything is written or printed.
    std::optional<render::NoiseFloor> floor;
    if (floor_args.images.size() == 2) {
        const std::string &reference2_path = floor_args.images[0], &test2_path = floor_args.images[1];
        floor = render::paired_noise_floor(reference, test, read_image(reference2_path), read_image(test2_path),
                                           options, reference_path, test_path, reference2_path, test2_path);
    } else if (floor_args.images.size() == 1) {
        floor = render::reference_noise_floor(reference, test, read_image(floor_args.images[0]), options,
                                              reference_path, test_path, floor_args.images[0]);
    }
    // No seed noise at all while the images differ: deterministic images, or (the usual cause)
    // the first seed's files given again.
    if (floor && floor->mse_noise == 0.0 && m.mse_display > 0.0)
        std::fprintf(stderr, "npf compare: warning: --floor: the second seed's images give exactly the first seed's "
                             "errors, so no noise is seen (infinite floor); were they rendered at another seed?\n");
    if (cl.has("--heatmap")) {
        const render::RelMseMap map = render::relmse_map(reference, test, options, reference_path, test_path);
        render::write_relmse_heatmap(cl.value("--heatmap"), map, heatmap_max);
    }

    const std::optional<std::string> heatmap = cl.has("--heatmap") ? std::optional<std::string>(cl.value("--heatmap")) : std::nullopt;
    const CompareResult result{reference_path, test_path, heatmap, heatmap_max, floor_args.images,
                               options.coverage, m, floor};
    if (cl.has("--json")) {
        print_json(result);
    } else {
        print_text(result);
    }
    return 0;
}

}  // namespace npf::cli
