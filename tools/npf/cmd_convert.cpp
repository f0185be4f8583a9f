// npf convert: a measured (or analytic) material to an NPF factor texture (docs/format.md).
#include "command_line.h"
#include "commands.h"
#include "progress.h"

#include <npf/converter/convert.h>
#include <npf/converter/open_material.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = {
    {"-o", true, "output factor texture (.exr), required"},
    {"--preset", true, "preview, production (default), fine or paper (the paper's pure model; docs/fitting.md)"},
    {"--wavelengths", true, "channels to fit: rgb, start:end:count or a,b,c nm (default: the source's)"},
    {"--max-wavelengths", true, "keep at most this many of the source's wavelengths, evenly spread"},
    {"--isotropy", true, "auto (default: as the source), isotropic or anisotropic"},
    {"--grid", true, "fitting grid THETA_H,PHI_H,THETA_D,PHI_D (D and F tables)"},
    {"--g-grid", true, "G table THETA,PHI"},
    {"--phi-d-samples", true, "phi_d samples per ring (0: every grid cell)"},
    {"--pca", true, "cumulative contribution ratios D,G kept by the SVD (e.g. 0.99,0.95; 1 = lossless)"},
    {"--rank", true, "fixed SVD ranks D,G (overrides --pca)"},
    {"--importance", true, "w_I powers: P for (cos_i cos_o)^P, or PV,PL for cos_i^PV cos_o^PL (1,2 weighs errors as a render does; docs/fitting.md)"},
    {"--compressive", true, "w_C power q: (rho + eps)^-q"},
    {"--epsilon", true, "w_C epsilon (1/sr)"},
    {"--volume-weight", true, "paper (default) or three-angle (Bagher et al.)"},
    {"--iterations", true, "most AWLS sweeps per block of channels"},
    {"--tolerance", true, "stop when a sweep lowers the weighted error by less than this, relative"},
    {"--g-prior", true, "smith (G starts from Smith's masking of D and stays <= 1), smith-start (starts there only), bounded (G <= 1 only) or free"},
    {"--plain", false, "no line-search extrapolation (the paper's plain alternation)"},
    {"--detail", true, "detail layer grid THETA_H,THETA_D,PHI_D (u_h, theta_d, phi_d), or none (the paper's pure model; docs/fitting.md)"},
    {"--detail-energy", true, "weight of the detail fit's energy term (0: none; default 1e4)"},
    {"--horizon", true, "closed (default; preview and production: G falls to 0 at the horizon, no light gained at silhouettes) or open (G as fitted; the paper preset)"},
    {"--detail-weight", true, "power p of the detail fit's display weight (f + eps)^-p (default 1.17; 0: plain least squares)"},
    {"--detail-views", true, "view angles (degrees) at which the detail fit holds the source's albedo"},
    {"--error-pairs", true, "direction pairs of the BRDF-space error (0 skips it)"},
    {"--target-psnr", true, "predicted render PSNR to reach (dB): writes the smallest detail layer (none, 16x8x16 .. 64x32x64) that reaches it, or the best with a warning"},
    {"--target-grids", true, "with --target-psnr: the detail grids to try after none, growing (default 16x8x16,24x10x24,32x12x32,40x20x40,48x24x48,64x32x64)"},
    {"--no-predict", false, "skip the predicted render PSNR (4 renders of 128x128 at 64 spp: a few seconds)"},
    {"--threads", true, "threads (default: all cores)"},
    {"--quiet", false, "no progress bar"},
    {"--help", false, "show this help"},
};

long whole(const std::string& flag, const std::string& v, long lo, long hi) {
    char* end = nullptr;
    const long n = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || n < lo || n > hi) {
        throw Error(flag, "needs a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" + v + "'");
    }
    return n;
}

double number(const std::string& flag, const std::string& v) {
    char* end = nullptr;
    const double d = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || !std::isfinite(d)) throw Error(flag, "'" + v + "' is not a number");
    return d;
}

// "a,b,..." with exactly `count` parts.
std::vector<std::string> parts(const std::string& flag, const std::string& v, std::size_t count) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = v.find(',', start);
        out.push_back(v.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (count > 0 && out.size() != count) throw Error(flag, "expects " + std::to_string(count) + " comma-separated values, got '" + v + "'");
    return out;
}

std::string megabytes(std::uint64_t bytes) {
    char b[32];
    std::snprintf(b, sizeof b, "%.2f MB", double(bytes) / 1e6);
    return b;
}

}  // namespace

int run_convert(const std::vector<std::string>& args) {
    CommandLine cl("convert", args, kFlags);
    if (cl.has("--help") || cl.positional().size() != 1 || !cl.has("-o")) {
        std::printf("usage: npf convert IN -o OUT.exr [--preset preview|production|fine|paper] [settings]\n\n"
                    "Fits the NPF factors (paper Eq. 1) to a material: an RGL .bsdf, MERL .binary, NPF texture .exr\n"
                    "or Neural BRDF .h5 file, or an analytic recipe (.yaml, configs/materials/); compresses D and G\n"
                    "across wavelengths; writes the factor texture. Settings override the preset. Example:\n"
                    "  npf convert satin.bsdf -o satin.exr --preset production --wavelengths 380:780:81\n\n%s",
                    usage_lines(kFlags).c_str());
        return cl.has("--help") ? 0 : 2;
    }
    const std::string input = cl.positional()[0], output = cl.value("-o");
    const std::unique_ptr<Brdf> source = open_material(input);

    Isotropy isotropy = Isotropy::Auto;
    if (cl.has("--isotropy")) {
        const std::string v = cl.value("--isotropy");
        if (v == "isotropic") isotropy = Isotropy::Isotropic;
        else if (v == "anisotropic") isotropy = Isotropy::Anisotropic;
        else if (v != "auto") throw Error("--isotropy", "'" + v + "' is not auto, isotropic or anisotropic");
    }
    const bool isotropic = isotropy == Isotropy::Auto ? source->info().isotropic : isotropy == Isotropy::Isotropic;
    const ConvertPreset preset = parse_convert_preset(cl.value("--preset", "production"), "--preset");
    ConvertSettings s = preset_settings(preset, isotropic);
    s.isotropy = isotropy;
    AwlsOptions& o = s.fit;
    if (cl.has("--wavelengths")) {
        s.wavelengths = cl.value("--wavelengths");
        parse_channel_list(s.wavelengths, "--wavelengths");  // a bad list names the flag (the fit parses it again)
    }
    if (cl.has("--max-wavelengths")) s.max_wavelengths = int(whole("--max-wavelengths", cl.value("--max-wavelengths"), 0, 100000));
    if (cl.has("--grid")) {
        const auto p = parts("--grid", cl.value("--grid"), 4);
        o.grid = {int(whole("--grid", p[0], 2, 4096)), int(whole("--grid", p[1], 1, 4096)), int(whole("--grid", p[2], 2, 4096)),
                  int(whole("--grid", p[3], 2, 4096))};
    }
    if (cl.has("--g-grid")) {
        const auto p = parts("--g-grid", cl.value("--g-grid"), 2);
        o.g_theta = int(whole("--g-grid", p[0], 2, 4096));
        o.g_phi = int(whole("--g-grid", p[1], 1, 4096));
    }
    if (cl.has("--phi-d-samples")) o.phi_d_samples = int(whole("--phi-d-samples", cl.value("--phi-d-samples"), 0, 4096));
    if (cl.has("--pca")) {
        const auto p = parts("--pca", cl.value("--pca"), 2);
        s.compression.d_ratio = number("--pca", p[0]);
        s.compression.g_ratio = number("--pca", p[1]);
        for (double r : {s.compression.d_ratio, s.compression.g_ratio}) {
            if (!(r > 0.0 && r <= 1.0)) throw Error("--pca", "ratios must lie in (0, 1]");
        }
    }
    if (cl.has("--pca") || cl.has("--rank")) s.compress_rgb = true;
    if (cl.has("--rank")) {
        const auto p = parts("--rank", cl.value("--rank"), 2);
        s.compression.d_rank = int(whole("--rank", p[0], 1, 100000));
        s.compression.g_rank = int(whole("--rank", p[1], 1, 100000));
    }
    if (cl.has("--importance")) {
        const std::string v = cl.value("--importance");
        if (v.find(',') == std::string::npos) {
            o.importance_power_view = o.importance_power_light = number("--importance", v);
        } else {
            const auto p = parts("--importance", v, 2);
            o.importance_power_view = number("--importance", p[0]);
            o.importance_power_light = number("--importance", p[1]);
        }
    }
    if (cl.has("--compressive")) o.compressive_power = number("--compressive", cl.value("--compressive"));
    if (cl.has("--epsilon")) {
        o.compressive_epsilon = number("--epsilon", cl.value("--epsilon"));
        if (!(o.compressive_epsilon > 0.0)) throw Error("--epsilon", "must be positive");
    }
    if (cl.has("--volume-weight")) {
        const std::string v = cl.value("--volume-weight");
        if (v == "paper") o.volume_weight = VolumeWeight::Paper;
        else if (v == "three-angle") o.volume_weight = VolumeWeight::ThreeAngle;
        else throw Error("--volume-weight", "'" + v + "' is not paper or three-angle");
    }
    if (cl.has("--iterations")) o.max_iterations = int(whole("--iterations", cl.value("--iterations"), 1, 100000));
    if (cl.has("--tolerance")) {
        o.tolerance = number("--tolerance", cl.value("--tolerance"));
        if (!(o.tolerance >= 0.0)) throw Error("--tolerance", "must not be negative");
    }
    if (cl.has("--plain")) o.acceleration = AwlsOptions::Acceleration::None;
    if (cl.has("--g-prior")) {
        const std::string v = cl.value("--g-prior");
        if (v == "smith") o.smith_start = o.bound_g = true;
        else if (v == "smith-start") o.smith_start = true, o.bound_g = false;
        else if (v == "bounded") o.smith_start = false, o.bound_g = true;
        else if (v == "free") o.smith_start = o.bound_g = false;
        else throw Error("--g-prior", "'" + v + "' is not smith, smith-start, bounded or free");
    }
    if (cl.has("--detail")) {
        const std::string v = cl.value("--detail");
        if (v == "none") {
            s.detail.grid = DetailGrid{};
        } else {
            s.detail.grid = parse_detail_grid(v, ',', "--detail");
        }
    }
    if (cl.has("--detail-energy")) {
        s.detail.energy_weight = number("--detail-energy", cl.value("--detail-energy"));
        if (!(s.detail.energy_weight >= 0.0)) throw Error("--detail-energy", "must not be negative");
    }
    if (cl.has("--horizon")) {
        const std::string v = cl.value("--horizon");
        if (v == "closed") s.close_horizon = true;
        else if (v == "open") s.close_horizon = false;
        else throw Error("--horizon", "'" + v + "' is not closed or open");
    }
    if (cl.has("--detail-weight")) {
        s.detail.display_power = number("--detail-weight", cl.value("--detail-weight"));
        if (!(s.detail.display_power >= 0.0 && s.detail.display_power <= 4.0)) throw Error("--detail-weight", "must lie in [0, 4]");
    }
    if (cl.has("--detail-views")) {
        s.detail.energy_views_deg.clear();
        for (const std::string& v : parts("--detail-views", cl.value("--detail-views"), 0)) {
            s.detail.energy_views_deg.push_back(number("--detail-views", v));
        }
    }
    if (cl.has("--error-pairs")) s.error_pairs = int(whole("--error-pairs", cl.value("--error-pairs"), 0, 100000000));
    if (cl.has("--threads")) o.threads = int(whole("--threads", cl.value("--threads"), 1, 1024));
    if (cl.has("--no-predict")) s.predict_psnr = false;
    if (cl.has("--target-psnr")) {
        s.target_psnr = parse_target_psnr(cl.value("--target-psnr"), "--target-psnr");
        // The target chooses the detail grid, by the prediction.
        if (cl.has("--detail")) throw Error("--target-psnr", "chooses the detail grid itself; leave out --detail");
        if (!s.predict_psnr) throw Error("--target-psnr", "needs the prediction; leave out --no-predict");
        if (cl.has("--target-grids")) s.target_ladder = parse_detail_ladder(cl.value("--target-grids"), "--target-grids");
    } else if (cl.has("--target-grids")) {
        throw Error("--target-grids", "needs --target-psnr");
    }

    check_output_path(output);  // a destination that cannot be written fails now, not after the fit
    ProgressBar bar("convert " + output, !cl.has("--quiet"));
    const ConvertReport r = convert_material(*source, output, s, [&bar](double f) { bar.update(f); });
    bar.finish();

    const RusinkiewiczGrid& g = o.grid;
    std::printf("wrote %s (%s preset)\n", output.c_str(), convert_preset_name(preset));
    std::printf("  factors     %s, %zu %s; D %dx%d, F %d, G %dx%d; %zu samples%s\n", r.isotropic ? "isotropic" : "anisotropic",
                r.channels.size(), r.channels.is_rgb() ? "RGB channels" : "wavelengths", g.theta_h, r.isotropic ? 1 : g.phi_h,
                g.theta_d, o.g_theta, r.isotropic ? 1 : o.g_phi, r.fit.samples,
                r.fit.invalid_values ? (", " + std::to_string(r.fit.invalid_values) + " invalid values ignored").c_str() : "");
    std::printf("  SVD ranks   D %d (kept %.4f), G %d (kept %.4f)\n", r.d_rank, r.d_kept_ratio, r.g_rank, r.g_kept_ratio);
    if (r.input_bytes > 0) {
        // "1/N" for what shrinks; a (small, synthetic) source can be smaller than its conversion.
        const double ratio = double(r.input_bytes) / double(std::max<std::uint64_t>(1, r.output_bytes));
        char times[48];
        if (ratio >= 1.0) std::snprintf(times, sizeof times, "1/%.0f", ratio);
        else std::snprintf(times, sizeof times, "%.1f times its size", 1.0 / ratio);
        std::printf("  size        %s (%llu bytes) from %s: %.2f %% of the input (%s)\n", megabytes(r.output_bytes).c_str(),
                    static_cast<unsigned long long>(r.output_bytes), megabytes(r.input_bytes).c_str(),
                    100.0 * double(r.output_bytes) / double(r.input_bytes), times);
    } else {
        std::printf("  size        %s (%llu bytes)\n", megabytes(r.output_bytes).c_str(), static_cast<unsigned long long>(r.output_bytes));
    }
    if (s.error_pairs > 0) {
        std::printf("  error       BRDF-space relative RMS %.3f %% mean, %.3f %% worst channel (fitted: %.3f %% / %.3f %%)\n",
                    100.0 * r.compressed_error.mean_relative_rms, 100.0 * r.compressed_error.max_relative_rms,
                    100.0 * r.fitted_error.mean_relative_rms, 100.0 * r.fitted_error.max_relative_rms);
    }
    if (s.close_horizon) {
        std::printf("  horizon     G closed at the horizon in %d of %d columns (no light gained at grazing views)\n",
                    r.horizon_columns_closed, r.isotropic ? 1 : o.g_phi);
    }
    if (r.detail_not_kept) {
        std::printf("  detail      fitted but not kept: BRDF-space relative RMS %.3f %% with it, %.3f %% without (its\n"
                    "              residual has no phi_h axis; on anisotropic materials the average over phi_h can miss)\n",
                    100.0 * r.detailed_error.mean_relative_rms, 100.0 * r.compressed_error.mean_relative_rms);
    }
    if (r.has_detail) {
        const DetailGrid& dg = r.detail_grid;
        std::printf("  detail      %dx%dx%d (u_h, theta_d, phi_d), rank %d; weighted error %.4g -> %.4g; albedo error at "
                    "the fit's views %.2f %% -> %.2f %%; %.1f s\n",
                    dg.theta_h, dg.theta_d, dg.phi_d, r.detail_rank, r.detail.weighted_error_before,
                    r.detail.weighted_error_after, 100.0 * r.detail.energy_error_before,
                    100.0 * r.detail.energy_error_after, r.detail.seconds);
        if (s.error_pairs > 0) {
            std::printf("  error       with the detail layer: BRDF-space relative RMS %.3f %% mean, %.3f %% worst channel\n",
                        100.0 * r.detailed_error.mean_relative_rms, 100.0 * r.detailed_error.max_relative_rms);
        }
    }
    std::printf("  albedo      at most %.3f (view %.0f deg, %s)\n", r.albedo_max, r.albedo_max_theta_deg,
                r.channels.name(r.albedo_max_channel).c_str());
    std::printf("  energy      directional albedo within %.2f %% of the source's at 0..80 deg (worst at %.0f deg, %s)\n",
                100.0 * r.energy_error, r.energy_error_theta_deg, r.channels.name(r.energy_error_channel).c_str());
    if (r.predicted) {
        char floor[64] = "";
        if (r.prediction.floor_psnr != 0.0) {
            std::snprintf(floor, sizeof floor, " (noise floor %.2f dB%s)", r.prediction.floor_psnr,
                          r.prediction.noise_limited ? ", noise-limited" : "");
        }
        std::printf("  predicted   render PSNR %.2f dB against the source%s; %s\n", r.prediction.psnr, floor,
                    r.prediction_settings.c_str());
    }
    if (s.target_psnr > 0.0) {
        std::string tried;
        for (const ConvertReport::TargetCandidate& c : r.target_candidates) {
            char b[96];
            if (c.grid.empty()) std::snprintf(b, sizeof b, "none %.2f", c.psnr);
            else std::snprintf(b, sizeof b, "%dx%dx%d %.2f", c.grid.theta_h, c.grid.theta_d, c.grid.phi_d, c.psnr);
            tried += (tried.empty() ? "" : ", ") + std::string(b);
        }
        std::printf("  target      %.2f dB %s: predicted %.2f dB with %s; tried (dB) %s\n", s.target_psnr,
                    r.target_met ? "met" : "NOT met", r.prediction.psnr,
                    r.has_detail ? "the detail layer above" : "no detail layer", tried.c_str());
        if (!r.target_met) {
            std::fprintf(stderr, "npf convert: warning: target %.2f dB not reached; wrote the best candidate, predicted %.2f dB\n",
                         s.target_psnr, r.prediction.psnr);
        }
    }
    if (r.albedo_unbounded_at_horizon) {
        std::printf("  horizon     G's last rows extrapolate above 0 at the horizon: the albedo grows without bound in the\n"
                    "              last fraction of a degree (silhouettes); cap it: npf edit %s -o CAPPED.exr --limit-albedo 1\n",
                    output.c_str());
    }
    if (r.albedo_max > kGainsLightAlbedo) {
        std::fprintf(stderr, "npf convert: warning: %s reflects more light than it receives at a %.0f degree view "
                             "(directional albedo %.3f); compare with the source: npf albedo %s --against %s; "
                             "cap it: npf edit %s -o CAPPED.exr --limit-albedo 1\n",
                     output.c_str(), r.albedo_max_theta_deg, r.albedo_max, output.c_str(), input.c_str(), output.c_str());
    }
    int most = 0;
    for (int it : r.fit.iterations) most = std::max(most, it);
    std::printf("  time        %.1f s: resampling %.1f, fitting %.1f (%d sweeps at most), SVD %.1f, error %.1f, "
                "prediction %.1f, writing %.1f; peak memory %.2f GiB\n",
                r.seconds, r.fit.seconds_resampling, r.fit.seconds_fitting, most, r.seconds_compression, r.seconds_error,
                r.seconds_prediction, r.seconds_writing, r.peak_memory_gib);
    return 0;
}

}  // namespace npf::cli
