#include <npf/converter/convert.h>
#include "conversion_metadata.h"

#include <npf/shading/npf_texture_file.h>
#include <npf/core/directional_albedo.h>
#include <npf/shading/npf_albedo.h>
#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/core/text.h>
#include <npf/shading/npf_texture_layout.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_model.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <sys/resource.h>

namespace npf {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

double peak_memory_gib() {
    rusage u{};
    if (getrusage(RUSAGE_SELF, &u) != 0) return 0.0;
    return double(u.ru_maxrss) / (1024.0 * 1024.0);  // ru_maxrss is in KiB on Linux
}


Channels choose_channels(const Brdf& source, const ConvertSettings& s) {
    const Channels stored = source.info().channels;
    if (!s.wavelengths.empty()) return parse_channel_list(s.wavelengths, "wavelengths");
    if (stored.is_rgb() || s.max_wavelengths <= 0 || stored.size() <= std::size_t(s.max_wavelengths)) return stored;
    // Evenly spread over the stored list, both ends kept.
    const std::vector<float>& all = stored.wavelengths();
    std::vector<float> kept;
    const std::size_t n = std::size_t(std::max(2, s.max_wavelengths));
    for (std::size_t k = 0; k < n; ++k) kept.push_back(all[(k * (all.size() - 1) + (n - 1) / 2) / (n - 1)]);
    kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
    return Channels::spectral(kept);
}

// The largest |relative difference| of the model's directional albedo from the source's over the
// energy views (both at the model's channels).
void measure_energy_error(const Brdf& source, const NpfModel& model, int samples, int threads, ConvertReport& report) {
    const NpfBrdf converted(model);
    AlbedoTableOptions a;
    a.theta_deg = energy_error_views_deg();
    a.phi_deg = default_albedo_azimuths(model.isotropic() && source.info().isotropic);
    a.estimator.samples = samples;
    a.threads = threads;
    const std::vector<AlbedoRow> mine = directional_albedo_table(converted, converted.native_query(), a);
    const std::vector<AlbedoRow> theirs = directional_albedo_table(source, source.query(model.channels), a);
    const AlbedoDifference worst = largest_albedo_difference(mine, theirs);
    report.energy_error = std::fabs(worst.relative);
    report.energy_error_theta_deg = report.energy_error > 0.0 ? mine[worst.row].theta_deg : 0.0;
    report.energy_error_channel = report.energy_error > 0.0 ? worst.channel : 0;
}

// --target-psnr: the base alone, then each ladder grid, until one's predicted PSNR reaches the
// target; leaves the written candidate in `model`.
void search_detail_ladder(const Brdf& source, NpfModel& model, const ConvertSettings& settings, int threads,
                          const PsnrPredictor& predictor, ConvertReport& report, const std::function<void(double)>& progress) {
    std::vector<DetailGrid> ladder = {DetailGrid{}};
    ladder.insert(ladder.end(), settings.target_ladder.begin(), settings.target_ladder.end());
    // Progress by cells: the detail fit's cost grows with them, a prediction's does not.
    const auto cost = [](const DetailGrid& g) { return 1.0 + double(g.cells()) / 2048.0; };
    double total = 0.0, done = 0.0;
    for (const DetailGrid& g : ladder) total += cost(g);

    const NpfModel base = model;
    std::optional<NpfModel> best;
    DetailReport best_detail;
    double best_psnr = -std::numeric_limits<double>::infinity();
    for (const DetailGrid& g : ladder) {
        const auto start = Clock::now();
        NpfModel candidate = base;
        DetailReport detail;
        const double from = done / total, span = cost(g) / total;
        if (!g.empty()) {
            DetailOptions d = settings.detail;
            d.grid = g;
            if (d.threads == 0) d.threads = threads;
            detail = fit_detail_layer(source, candidate, d, [&](double f) {
                if (progress) progress(0.6 + 0.35 * (from + 0.9 * span * f));
            });
        }
        const PsnrPrediction p = predictor.predict(candidate, false);
        report.seconds_prediction += p.seconds;
        report.target_candidates.push_back({g, candidate.detail.rank, p.psnr, seconds_since(start)});
        done += cost(g);
        if (progress) progress(0.6 + 0.35 * done / total);
        // Strictly better only: of equal candidates the smaller (earlier) is kept.
        const bool met = p.psnr >= settings.target_psnr;
        if (met || p.psnr > best_psnr) {
            best_psnr = p.psnr;
            best = std::move(candidate);
            best_detail = detail;
        }
        if (met) {
            report.target_met = true;
            break;
        }
    }
    model = std::move(*best);
    report.has_detail = model.has_detail();
    report.detail = best_detail;
    report.detail_rank = model.detail.rank;
}

}  // namespace

double parse_target_psnr(const std::string& text, const std::string& what) {
    const std::optional<double> db = finite_number_of(text);
    if (!db) throw Error(what, "'" + text + "' is not a PSNR in dB (a number above 0)");
    check_target_psnr(*db, what);
    return *db;
}

void check_target_psnr(double db, const std::string& what) {
    if (!(std::isfinite(db) && db > 0.0)) throw Error(what, "a target PSNR must be a finite number of dB above 0, got " + number_text(db));
}

std::vector<DetailGrid> default_target_ladder() {
    return {{16, 8, 16}, {24, 10, 24}, {32, 24, 16}, {40, 20, 40}, {48, 24, 48}, {64, 32, 64}};
}

DetailGrid parse_detail_grid(const std::string& text, char separator, const std::string& what) {
    const std::string sep(1, separator);
    const std::string form = "H" + sep + "D" + sep + "P (u_h, theta_d, phi_d cells)";
    int v[3] = {0, 0, 0};
    const int most[3] = {1024, 1024, 4096};
    std::size_t start = 0;
    for (int k = 0; k < 3; ++k) {
        const std::size_t end = k < 2 ? text.find(separator, start) : text.size();
        if (end == std::string::npos) throw Error(what, "'" + text + "' is not " + form);
        const std::string part = text.substr(start, end - start);
        try {
            v[k] = int(parse_whole_number(part, 1, std::uint64_t(most[k]), what));
        } catch (const Error&) {
            throw Error(what, "'" + text + "' is not " + form + ", each a whole number in [1, " + std::to_string(most[k]) + "]");
        }
        start = end + 1;
    }
    return {v[0], v[1], v[2]};
}

std::vector<DetailGrid> parse_detail_ladder(const std::string& text, const std::string& what) {
    std::vector<DetailGrid> grids;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        grids.push_back(parse_detail_grid(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start), 'x', what));
        if (grids.size() > 1 && grids.back().cells() <= grids[grids.size() - 2].cells()) {
            throw Error(what, "the grids must grow in cells (the search writes the first, smallest, that reaches the target)");
        }
        if (comma == std::string::npos) return grids;
        start = comma + 1;
    }
}

std::vector<double> energy_error_views_deg() { return DetailOptions{}.energy_views_deg; }

ConvertPreset parse_convert_preset(const std::string& name, const std::string& what) {
    if (name == "preview") return ConvertPreset::Preview;
    if (name == "production") return ConvertPreset::Production;
    if (name == "fine") return ConvertPreset::Fine;
    if (name == "paper") return ConvertPreset::Paper;
    throw Error(what, "'" + name + "' is not a preset (preview, production, fine or paper)");
}

const char* convert_preset_name(ConvertPreset p) {
    switch (p) {
    case ConvertPreset::Preview: return "preview";
    case ConvertPreset::Production: return "production";
    case ConvertPreset::Fine: return "fine";
    case ConvertPreset::Paper: return "paper";
    }
    return "?";
}

namespace {

// The name a conversion's errors carry: the source's path ("convert" for one in memory).
std::string source_name(const BrdfInfo& info) { return info.path.empty() ? "convert" : info.path; }

// A conversion whose tables no factor texture may hold (docs/format.md sec. 8) would fit for
// hours and then be refused by the writer: refused now.
void check_table_sizes(const AwlsOptions& f, const BrdfInfo& info) {
    const auto cells = [](int a, int b) { return std::uint64_t(std::max(a, 1)) * std::uint64_t(std::max(b, 1)); };
    if (cells(f.grid.theta_h, f.grid.phi_h) > NpfModel::kMaxTableCells || cells(f.g_theta, f.g_phi) > NpfModel::kMaxTableCells)
        throw Error(source_name(info),
                    "the fitting grid's D (" + std::to_string(f.grid.theta_h) + " x " + std::to_string(f.grid.phi_h) + ") or G (" +
                        std::to_string(f.g_theta) + " x " + std::to_string(f.g_phi) + ") has more than the " +
                        std::to_string(NpfModel::kMaxTableCells) + " cells a factor texture may hold");
}

// The source's renders first: a missing environment map fails before the long fit.
std::optional<PsnrPredictor> start_prediction(const Brdf& source, const ConvertSettings& settings, bool target, ConvertReport& report) {
    std::optional<PsnrPredictor> predictor;
    if (settings.predict_psnr || target) {
        const auto t0 = Clock::now();
        PsnrPredictionOptions p = settings.prediction;
        if (p.threads == 0) p.threads = settings.fit.threads;
        predictor.emplace(source, p);
        report.prediction_settings = predictor->settings_text();
        report.seconds_prediction += seconds_since(t0);
    }
    return predictor;
}

// The fitter's options for this source: its channels, and no phi axes for isotropic factors.
AwlsOptions fit_options(const Brdf& source, const ConvertSettings& settings, ConvertReport& report) {
    const BrdfInfo& info = source.info();
    report.isotropic = settings.isotropy == Isotropy::Auto ? info.isotropic : settings.isotropy == Isotropy::Isotropic;
    AwlsOptions o = settings.fit;
    o.channels = report.channels = choose_channels(source, settings);
    if (report.isotropic) {
        o.grid.phi_h = 1;
        o.g_phi = 1;
    } else if (o.grid.phi_h == 1 || o.g_phi == 1) {
        throw Error(source_name(info), "anisotropic factors need phi_h and G phi sizes above 1");
    }
    return o;
}

NpfFactors fit_factors(const Brdf& source, const AwlsOptions& o, ConvertReport& report) {
    NpfFactors factors = fit_npf(source, o, &report.fit);
    // A NaN or infinite source value gets no weight in the fit; a conversion that silently drops
    // data is wrong with exit 0, so it fails (the readers' value bounds make this a defect).
    if (report.fit.invalid_values > 0)
        throw Error(source_name(source.info()),
                    std::to_string(report.fit.invalid_values) +
                        " source values at the fit's samples are not finite (NaN or infinite): the conversion would drop them");
    return factors;
}

// Factors that could give values no material reaches are the fit's fault, not the source's: say
// so here, before the file's own check calls the tables corrupt (core/brdf.h).
void check_value_bound(const NpfModel& model, const ConvertSettings& settings, const BrdfInfo& info) {
    const double bound = model.value_bound();
    if (bound <= kMaxMaterialValue) return;
    std::size_t worst = 0;
    double f_largest = 0.0;
    for (std::size_t c = 0; c < model.channel_count(); ++c) {
        const float* f = model.F.data() + c * std::size_t(model.f_theta);
        const double m = *std::max_element(f, f + model.f_theta);
        if (m > f_largest) f_largest = m, worst = c;
    }
    char text[320];
    std::snprintf(text, sizeof text,
                  "the fit is degenerate: its factors could give f_r cos(theta_i) cos(theta_o) up to %.3g 1/sr (largest F "
                  "%.3g, channel %s), above the %.0e a material may reach; nothing written%s",
                  bound, f_largest, model.channels.name(worst).c_str(), kMaxMaterialValue,
                  settings.preset == ConvertPreset::Production ? "" : " (the production preset may fit it: --preset production)");
    throw Error(source_name(info), text);
}

// The SVD across channels (RGB stays lossless unless asked), then the horizon closed.
NpfModel compress_model(const NpfFactors& factors, const ConvertSettings& settings, const CompressionOptions& compression,
                        ConvertReport& report) {
    const auto t = Clock::now();
    NpfModel model = compress_factors(factors, compression);
    report.seconds_compression = seconds_since(t);
    report.d_rank = model.D.rank;
    report.g_rank = model.G.rank;
    report.d_kept_ratio = model.D.kept_ratio;
    report.g_kept_ratio = model.G.kept_ratio;
    if (settings.close_horizon) report.horizon_columns_closed = model.close_g_at_horizon();
    return model;
}

// The detail layer: the ladder's choice with a target, else the settings' grid (if any).
void add_detail_layer(const Brdf& source, NpfModel& model, const ConvertSettings& settings, int threads, const PsnrPredictor* predictor,
                      ConvertReport& report, const std::function<void(double)>& progress) {
    if (predictor && settings.target_psnr != 0.0) {
        search_detail_ladder(source, model, settings, threads, *predictor, report, progress);
    } else if (!settings.detail.grid.empty()) {
        DetailOptions d = settings.detail;
        if (d.threads == 0) d.threads = threads;
        report.detail = fit_detail_layer(source, model, d, [&](double f) {
            if (progress) progress(0.9 + 0.05 * f);
        });
        report.has_detail = true;
        report.detail_rank = model.detail.rank;
    }
    report.detail_grid = model.detail_grid;
}

NpfModel without_detail_layer(NpfModel model) {
    model.detail_grid = DetailGrid{};
    model.detail = SpectralBasis{};
    return model;
}

// The BRDF-space errors of the fitted factors, the compressed ones and the detailed model, and
// the held-out comparison of what is written.
void measure_brdf_errors(const Brdf& source, const NpfFactors& factors, const NpfModel& model, const Channels& channels,
                         int pairs, ConvertReport& report, const std::function<void(double)>& progress) {
    const std::size_t C = factors.channel_count();
    report.fitted_error = brdf_space_error(source, channels, [&](const Vec3& wi, const Vec3& wo, double* out) {
        const Vec3d a{wi.x, wi.y, wi.z}, b{wo.x, wo.y, wo.z};
        for (std::size_t c = 0; c < C; ++c) out[c] = factors.eval(c, a, b);
    }, pairs);
    if (progress) progress(0.95);
    const NpfModel without_detail = without_detail_layer(model);
    report.compressed_error = brdf_space_error(source, channels, [&](const Vec3& wi, const Vec3& wo, double* out) {
        without_detail.eval_all(wi, wo, out);
    }, pairs);
    if (report.has_detail) {
        report.detailed_error = brdf_space_error(source, channels, [&](const Vec3& wi, const Vec3& wo, double* out) {
            model.eval_all(wi, wo, out);
        }, pairs);
    }
    report.held_out = compare_brdfs(NpfBrdf(model), source, model.channels, held_out_pairs());
}

// The residual has no phi_h axis: on an anisotropic material it is the average over phi_h, which
// can miss every azimuth. There it is kept only where the held-out BRDF-space error (f_r cos at
// pairs no fit saw, pooled over channels: docs/metrics.md sec. 14) says it helps. Not on
// isotropic ones, and not with a target (the predicted render decides there).
void keep_detail_if_better(const Brdf& source, NpfModel& model, const ConvertSettings& settings, ConvertReport& report) {
    if (!report.has_detail || settings.error_pairs <= 0 || !settings.detail_only_if_better || settings.target_psnr != 0.0 ||
        model.isotropic())
        return;
    NpfModel without_detail = without_detail_layer(model);
    const BrdfComparisonResult plain = compare_brdfs(NpfBrdf(without_detail), source, model.channels, held_out_pairs());
    if (!(report.held_out.relative_rms < plain.relative_rms)) {
        report.detail_not_kept_held_out_rms = report.held_out.relative_rms;
        model = std::move(without_detail);
        report.held_out = plain;
        report.has_detail = false;
        report.detail_grid = DetailGrid{};
        report.detail_not_kept = true;
    }
}

// Energy: a fit can gain light where the data are thin (grazing views beyond the measured range).
void measure_energy(const Brdf& source, const NpfModel& model, const ConvertSettings& settings, int threads, ConvertReport& report) {
    const EnergyCheck e = energy_check(model, threads);
    report.albedo_max = e.albedo_max;
    report.albedo_max_theta_deg = e.theta_deg;
    report.albedo_max_channel = e.channel;
    report.albedo_unbounded_at_horizon = e.unbounded_at_horizon;
    measure_energy_error(source, model, settings.energy_error_samples, threads, report);
}

Conversion convert_stages(const Brdf& source, const ConvertSettings& settings, const std::function<void(double)>& progress) {
    const auto start = Clock::now();
    const BrdfInfo& info = source.info();
    ConvertReport report;
    report.input_bytes = info.file_bytes;
    const bool target = settings.target_psnr != 0.0;
    if (target) check_target_psnr(settings.target_psnr, "target_psnr");
    check_table_sizes(settings.fit, info);
    std::optional<PsnrPredictor> predictor = start_prediction(source, settings, target, report);

    AwlsOptions o = fit_options(source, settings, report);
    // Fitting is most of the time; the error measurement and writing the rest (with a target,
    // the ladder's detail fits take a share).
    const double fit_share = target ? 0.6 : 0.9;
    o.progress = [&](double f) {
        if (progress) progress(fit_share * f);
    };
    const NpfFactors factors = fit_factors(source, o, report);

    CompressionOptions compression = settings.compression;
    if (o.channels.is_rgb() && !settings.compress_rgb) compression = CompressionOptions{};
    NpfModel model = compress_model(factors, settings, compression, report);
    check_value_bound(model, settings, info);
    add_detail_layer(source, model, settings, o.threads, predictor ? &*predictor : nullptr, report, progress);

    const auto t = Clock::now();
    if (settings.error_pairs > 0) measure_brdf_errors(source, factors, model, o.channels, settings.error_pairs, report, progress);
    keep_detail_if_better(source, model, settings, report);
    measure_energy(source, model, settings, o.threads, report);
    report.seconds_error = seconds_since(t);
    if (predictor) {
        // Again for the written model, now with its noise floor (a target's search rendered the
        // candidates at one seed only; the same seed gives the same PSNR).
        report.prediction = predictor->predict(model, true);
        report.predicted = true;
        report.seconds_prediction += report.prediction.seconds;
    }

    record_conversion(model, info, settings, o, compression, report);

    report.seconds = seconds_since(start);
    report.peak_memory_gib = peak_memory_gib();
    return {std::move(model), std::move(report)};
}

}  // namespace

Conversion convert(const Brdf& source, const ConvertSettings& settings, const std::function<void(double)>& progress) {
    // Every error names the material: a stage's own ("detail layer: ...") gets the source's path in
    // front; the source's own stays as it is.
    const std::string& path = source.info().path;
    try {
        return convert_stages(source, settings, progress);
    } catch (const Error& e) {
        if (path.empty() || e.source() == path) throw;
        throw Error(path, e.what());
    }
}

ConvertReport convert_material(const Brdf& source, const std::string& output, const ConvertSettings& settings,
                               const std::function<void(double)>& progress) {
    const auto start = Clock::now();
    Conversion c = convert(source, settings, progress ? [&progress](double f) { progress(0.99 * f); } : std::function<void(double)>{});
    const auto t = Clock::now();
    c.report.output_bytes = write_npf_texture(c.model, output);
    c.report.seconds_writing = seconds_since(t);
    if (progress) progress(1.0);
    c.report.seconds = seconds_since(start);
    return std::move(c.report);
}

}  // namespace npf
