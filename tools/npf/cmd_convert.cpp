// npf convert: a measured (or analytic) material to an NPF factor texture (docs/format.md).
#include "command_line.h"
#include "commands.h"
#include "file_uses.h"
#include "progress.h"

#include <npf/converter/convert.h>
#include <npf/converter/convert_settings_table.h>
#include <npf/materials/open_material.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>

namespace npf::cli {

namespace {

// The settings' flags and help come from the table (convert_settings_table.h).
std::vector<FlagSpec> convert_flags() {
    std::vector<FlagSpec> flags = {{"-o", true, "output factor texture (.exr), required"}};
    for (const ConvertSettingRow& row : convert_settings_table()) {
        flags.push_back({setting_flag(row), row.kind != SettingKind::Switch, setting_help(row)});
    }
    flags.push_back({"--quiet", false, "no progress bar"});
    return flags;
}

std::string megabytes(std::uint64_t bytes) {
    char b[32];
    std::snprintf(b, sizeof b, "%.2f MB", double(bytes) / 1e6);
    return b;
}

const char* kHelp =
    "usage: npf convert IN -o OUT.exr [--preset preview|production|fine|paper] [settings]\n\n"
    "Fits the NPF factors (paper Eq. 1) to a material: an RGL .bsdf, MERL .binary, NPF texture .exr\n"
    "or Neural BRDF .h5 file, or an analytic recipe (.yaml, configs/materials/); compresses D and G\n"
    "across wavelengths; writes the factor texture. Settings override the preset. Example:\n"
    "  npf convert satin.bsdf -o satin.exr --preset production --wavelengths 380:780:81\n\n";

// The settings given on the command line, each checked (a bad value fails before the material is
// read), in the table's order; nothing for a setting not given.
std::vector<std::optional<SettingValue>> given_settings(const CommandLine& cl, const ConvertSettingsTable& table) {
    std::vector<std::optional<SettingValue>> given;
    for (const ConvertSettingRow& row : table) {
        const std::string flag = setting_flag(row);
        if (!cl.has(flag)) given.emplace_back();
        else given.push_back(check_setting(row, row.kind == SettingKind::Switch ? "true" : cl.value(flag), flag));
    }
    return given;
}

// The fit: factors, ranks, size, errors against the source and the horizon.
void print_fit(const ConvertReport& r, const ConvertSettings& s) {
    const AwlsOptions& o = s.fit;
    const RusinkiewiczGrid& g = o.grid;
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
    if (s.error_pairs > 0) {
        const BrdfComparisonResult& h = r.held_out;
        const auto angle = [](const Vec3& w) { return std::acos(std::min(1.0, std::max(-1.0, double(w.z)))) * 180.0 / kPiD; };
        std::printf("  held out    relative RMS of f_r cos %.4f at %zu pairs (%.4f within 60 deg); largest difference %.4g\n"
                    "              against %.4g (%s) at %.0f deg in, %.0f deg out (npf eval --against)\n",
                    h.relative_rms, h.used, h.relative_rms_60, h.worst.test, h.worst.reference,
                    r.channels.name(h.worst.channel).c_str(), angle(h.worst.wi), angle(h.worst.wo));
    }
    if (s.close_horizon) {
        std::printf("  horizon     G closed at the horizon in %d of %d columns (no light gained at grazing views)\n",
                    r.horizon_columns_closed, r.isotropic ? 1 : o.g_phi);
    }
}

// The detail layer, kept or not, and what it changed.
void print_detail(const ConvertReport& r, const ConvertSettings& s) {
    if (r.detail_not_kept) {
        std::printf("  detail      fitted but not kept: held-out relative RMS of f_r cos %.4f with it, %.4f without (its\n"
                    "              residual has no phi_h axis; on anisotropic materials the average over phi_h can miss)\n",
                    r.detail_not_kept_held_out_rms, r.held_out.relative_rms);
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
}

// The energy check and the predicted render PSNR (per lighting for a set).
void print_albedo_and_prediction(const ConvertReport& r) {
    std::printf("  albedo      at most %.3f (view %.0f deg, %s)\n", r.albedo_max, r.albedo_max_theta_deg,
                r.channels.name(r.albedo_max_channel).c_str());
    std::printf("  energy      directional albedo within %.2f %% of the source's at 0..80 deg (worst at %.0f deg, %s)\n",
                100.0 * r.energy_error, r.energy_error_theta_deg, r.channels.name(r.energy_error_channel).c_str());
    if (r.predicted) {
        // " (noise floor ...)" after a PSNR: none where not measured, infinite for a render with no samples.
        const auto floor_text = [](double floor_psnr, bool noise_limited) {
            char text[64] = "";
            if (std::isinf(floor_psnr)) std::snprintf(text, sizeof text, " (no noise floor: no Monte Carlo)");
            else if (floor_psnr != 0.0)
                std::snprintf(text, sizeof text, " (noise floor %.2f dB%s)", floor_psnr, noise_limited ? ", noise-limited" : "");
            return std::string(text);
        };
        if (r.prediction.lightings.size() > 1) {
            // A set: one line per lighting, then the worst, which is what a target meets.
            for (const LightingPrediction& l : r.prediction.lightings) {
                std::printf("  predicted   %-12s %.2f dB%s\n", l.lighting.c_str(), l.psnr,
                            floor_text(l.floor_psnr, l.noise_limited).c_str());
            }
            std::printf("  predicted   render PSNR %.2f dB against the source, the worst (%s); %s\n", r.prediction.psnr,
                        r.prediction.worst.c_str(), r.prediction_settings.c_str());
        } else {
            std::printf("  predicted   render PSNR %.2f dB against the source%s; %s\n", r.prediction.psnr,
                        floor_text(r.prediction.floor_psnr, r.prediction.noise_limited).c_str(), r.prediction_settings.c_str());
        }
    }
}

// --target-psnr: the candidates tried and whether the target was met.
void print_target(const ConvertReport& r, const ConvertSettings& s) {
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
}

// Where the result reflects more light than it receives: what to do about it.
void print_albedo_warnings(const ConvertReport& r, const std::string& input, const std::string& output) {
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
}

void print_times(const ConvertReport& r) {
    int most = 0;
    for (int it : r.fit.iterations) most = std::max(most, it);
    std::printf("  time        %.1f s: resampling %.1f, fitting %.1f (%d sweeps at most), SVD %.1f, error %.1f, "
                "prediction %.1f, writing %.1f; peak memory %.2f GiB\n",
                r.seconds, r.fit.seconds_resampling, r.fit.seconds_fitting, most, r.seconds_compression, r.seconds_error,
                r.seconds_prediction, r.seconds_writing, r.peak_memory_gib);
}

}  // namespace

int run_convert(const std::vector<std::string>& args) {
    const CommandLine cl = read_command_line(kHelp, convert_flags(), args);
    cl.expect_positional(1, 1, "one IN");
    cl.require("-o");
    const std::string input = cl.positional()[0], output = cl.value("-o");
    const ConvertSettingsTable& table = convert_settings_table();
    const std::vector<std::optional<SettingValue>> given = given_settings(cl, table);
    FileUses().input(input, "the input").output(output, "-o").check();
    const std::unique_ptr<Brdf> source = open_material(input);
    const ConvertSettings s = resolve_convert_settings(
        table, [&](const ConvertSettingRow& row) { return given[std::size_t(&row - table.data())]; },
        [](const ConvertSettingRow& row) { return setting_flag(row); }, source->info().isotropic);

    check_output_path(output);  // a destination that cannot be written fails now, not after the fit
    ProgressBar bar("convert " + output, !cl.has("--quiet"));
    const ConvertReport r = convert_material(*source, output, s, [&bar](double f) { bar.update(f); });
    bar.finish();

    std::printf("wrote %s (%s preset)\n", output.c_str(), convert_preset_name(s.preset));
    print_fit(r, s);
    print_detail(r, s);
    print_albedo_and_prediction(r);
    print_target(r, s);
    print_albedo_warnings(r, input, output);
    print_times(r);
    return 0;
}

}  // namespace npf::cli
