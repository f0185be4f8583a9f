// One material to one NPF factor texture: resample and fit (AWLS), compress D and G across
// channels (SVD), measure the errors, write the EXR atomically. What `npf convert` and the
// batch runner call; the presets are the speed/accuracy trade-offs measured in docs/fitting.md.
#pragma once

#include <npf/fit/awls.h>
#include <npf/fit/detail_fit.h>
#include <npf/fit/fit_error.h>
#include <npf/fit/spectral_compression.h>
#include <npf/converter/psnr_prediction.h>
#include <npf/core/brdf.h>
#include <npf/core/brdf_comparison.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace npf {

// The accuracy ladder: preview, production (the default) and fine carry a detail layer of
// growing resolution over the same NPF base; paper is the paper's pure model (no detail layer,
// G as fitted at the horizon), kept reproducible.
enum class ConvertPreset { Preview, Production, Fine, Paper };

// "preview", "production", "fine" or "paper"; throws npf::Error naming `what` otherwise.
ConvertPreset parse_convert_preset(const std::string& name, const std::string& what);
const char* convert_preset_name(ConvertPreset preset);

enum class Isotropy { Auto, Isotropic, Anisotropic };

// A target PSNR in dB (--target-psnr, batch target_psnr): a finite number above 0; throws
// npf::Error naming `what` otherwise. check_target_psnr is the same rule for a parsed value.
double parse_target_psnr(const std::string& text, const std::string& what);
void check_target_psnr(double db, const std::string& what);

// The detail grids --target-psnr tries after the base alone, in increasing size (cells): the
// preview and production grids, the fine one, and two beyond it.
std::vector<DetailGrid> default_target_ladder();
// A detail grid "H<sep>D<sep>P" (u_h, theta_d, phi_d; --detail "32,12,32"), and a list of them
// separated by commas, "16x8x16,32x12x32" (--target-grids), which must grow in cells. Throw
// npf::Error naming `what`.
DetailGrid parse_detail_grid(const std::string& text, char separator, const std::string& what);
std::vector<DetailGrid> parse_detail_ladder(const std::string& text, const std::string& what);

// Samples per axis of the energy error's albedo estimator (npf albedo --samples). 64 left a
// relative standard error of 4 % on a near-black channel (cg_sunflower's blue, albedo 0.03),
// which read as a 3.0 % error where 160 measure 0.7 %; 160 cost about a second.
inline constexpr int kEnergyErrorSamples = 160;

struct ConvertSettings {
    // Grid, weights, iterations, threads. The channels and, for isotropic factors, the phi
    // sizes are set by convert_material from the source and the fields below.
    AwlsOptions fit;
    CompressionOptions compression;
    // The detail layer fitted on top of the compressed factors (docs/fitting.md, "Detail layer");
    // an empty grid writes the paper's pure model (the paper preset). Its threads follow fit's.
    DetailOptions detail;
    // Close G at the horizon (NpfModel::close_g_at_horizon) before the detail fit, so that no
    // conversion gains light at grazing views; off in the paper preset (its pure model).
    bool close_horizon = false;
    // Anisotropic models keep the detail layer only when it lowers the BRDF-space error
    // (error_pairs > 0), the measurement independent of its fit.
    bool detail_only_if_better = true;
    // RGB factors are stored losslessly unless this is set: three channels gain little from the
    // SVD, and what little they gain costs visible colour error (docs/fitting.md).
    bool compress_rgb = false;
    // Which channels to fit: empty takes the source's own (RGB, or its wavelengths); "rgb", a
    // list "450,550,650" or "start:end:count" (nm) resamples the source's spectra.
    std::string wavelengths;
    // With `wavelengths` empty: keep at most this many of the source's wavelengths, evenly
    // spread, ends included (0: all).
    int max_wavelengths = 0;
    // Auto follows the source: isotropic sources get factors without phi axes.
    Isotropy isotropy = Isotropy::Auto;
    // Direction pairs of the BRDF-space error measurement (0 skips it).
    int error_pairs = 20000;
    // Samples per axis of the energy error's albedo estimator (kEnergyErrorSamples above; the
    // preview preset takes 96, a third of the cost, for a standard error 1.7 times larger).
    int energy_error_samples = kEnergyErrorSamples;
    ConvertPreset preset = ConvertPreset::Production;
    // Predict the paired-render PSNR of what is written (psnr_prediction.h); its threads follow
    // fit's when 0. Off (--no-predict) saves the renders' time.
    bool predict_psnr = true;
    PsnrPredictionOptions prediction;
    // Above 0: choose the detail layer by that prediction instead of `detail.grid`: the base alone,
    // then each grid of target_ladder in turn, each fitted with `detail`'s other options and
    // predicted; the first whose predicted PSNR reaches target_psnr (dB) is written, else the best
    // one (ConvertReport::target_met false). Needs the prediction (predict_psnr is implied).
    double target_psnr = 0.0;
    std::vector<DetailGrid> target_ladder = default_target_ladder();
};

// The settings of a preset, for a source that is isotropic or not (docs/fitting.md).
ConvertSettings preset_settings(ConvertPreset preset, bool isotropic);

struct ConvertReport {
    AwlsReport fit;
    bool isotropic = true;
    Channels channels;
    int d_rank = 0, g_rank = 0;
    double d_kept_ratio = 1.0, g_kept_ratio = 1.0;
    BrdfSpaceError fitted_error;      // the fitted factors before compression
    BrdfSpaceError compressed_error;  // the compressed factors, before any detail layer
    BrdfSpaceError detailed_error;    // what the file holds, with its detail layer (when it has one)
    // What the file holds against the source at the fixed held-out pairs (npf/core/brdf_comparison.h):
    // relative RMS of f_r cos(theta_o), pooled, and the largest difference (a peak too high or low).
    BrdfComparisonResult held_out;
    int horizon_columns_closed = 0;
    bool has_detail = false;
    // Fitted, but it did not lower the held-out BRDF-space error (anisotropic sources), which
    // was this with it (held_out: without it).
    bool detail_not_kept = false;
    double detail_not_kept_held_out_rms = 0.0;
    int detail_rank = 0;
    DetailGrid detail_grid;  // of the written model (empty without a detail layer)
    DetailReport detail;
    std::uint64_t input_bytes = 0, output_bytes = 0;
    double seconds_compression = 0.0, seconds_error = 0.0, seconds_writing = 0.0, seconds = 0.0;
    double peak_memory_gib = 0.0;     // of the process, when known
    // The largest directional albedo of the written model over a few view directions (0 to 89
    // degrees) and its channels, and where: above 1, the conversion reflects more light than it
    // receives there (docs/albedo.md). 0 when not measured (a model without channels).
    double albedo_max = 0.0, albedo_max_theta_deg = 0.0;
    std::size_t albedo_max_channel = 0;
    bool albedo_unbounded_at_horizon = false;  // EnergyCheck::unbounded_at_horizon
    // Energy error: the largest |relative difference| of the written model's directional albedo
    // from the source's over the views kEnergyErrorViewsDeg and the channels (npf albedo
    // --against's figure), and where.
    double energy_error = 0.0, energy_error_theta_deg = 0.0;
    std::size_t energy_error_channel = 0;
    // The predicted render PSNR of the written model (predicted false when not measured).
    bool predicted = false;
    PsnrPrediction prediction;
    std::string prediction_settings;  // PsnrPredictor::settings_text
    double seconds_prediction = 0.0;  // every render and comparison, the source's included
    // --target-psnr: each candidate tried, in order, and whether the written one reached the target.
    struct TargetCandidate {
        DetailGrid grid;  // empty: the base alone
        int detail_rank = 0;
        double psnr = 0.0;     // predicted
        double seconds = 0.0;  // its detail fit and prediction
    };
    std::vector<TargetCandidate> target_candidates;
    bool target_met = false;
};

// The views (degrees) of the energy error: those the detail fit holds (DetailOptions), 0 to 80;
// beyond 80 the measured files' own values are extrapolated (docs/fitting.md).
std::vector<double> energy_error_views_deg();

// Above this largest directional albedo a conversion is reported as gaining light: 1 plus 1 %,
// five times the energy check's accuracy (about 2e-3), so that no quadrature error triggers it.
inline constexpr double kGainsLightAlbedo = 1.01;

// A conversion: the model, with the metadata a factor texture of it stores (docs/format.md),
// and the report of how it was made.
struct Conversion {
    NpfModel model;
    ConvertReport report;
};

// Fits `source`, compresses and measures it; with settings.target_psnr, searches the detail
// ladder first (ConvertSettings). Writes nothing: the caller writes the model
// (write_npf_texture), edits it first, or shades it as it is. The progress callback gets the
// fraction done. Throws npf::Error naming the source.
Conversion convert(const Brdf& source, const ConvertSettings& settings, const std::function<void(double)>& progress = {});

// convert(), then the model written to `output` (NPF EXR; report.output_bytes and
// seconds_writing filled). Throws npf::Error (no file is left at `output`).
ConvertReport convert_material(const Brdf& source, const std::string& output, const ConvertSettings& settings,
                               const std::function<void(double)>& progress = {});

}  // namespace npf
