#include "conversion_metadata.h"

#include <npf/converter/convert_settings_table.h>
#include <npf/core/number_text.h>
#include <npf/shading/npf_texture_layout.h>

#include <algorithm>

namespace npf {

namespace {

using Metadata = std::vector<std::pair<std::string, std::string>>;

std::string grid_text(const DetailGrid& g) {
    return g.empty() ? "none" : std::to_string(g.theta_h) + "x" + std::to_string(g.theta_d) + "x" + std::to_string(g.phi_d);
}

void record_source(Metadata& m, const BrdfInfo& info) {
    m.emplace_back("source", info.path.empty() ? "(in memory: " + info.format + ")" : info.path);
    m.emplace_back("source_format", info.format);
    if (!info.description.empty()) m.emplace_back("source_description", info.description);
}

// The settings as fitted (after isotropy, with the detail grid written), from their rows.
void record_settings(Metadata& m, const ConvertSettings& settings, const AwlsOptions& fit, const DetailGrid& written) {
    ConvertSettings fitted = settings;
    fitted.fit = fit;
    fitted.detail.grid = written;
    for (auto& line : convert_settings_metadata(fitted)) m.push_back(std::move(line));
}

void record_fit(Metadata& m, const ConvertReport& report) {
    double worst_weighted = 0.0;
    int most_iterations = 0;
    for (std::size_t c = 0; c < report.fit.relative_error.size(); ++c) {
        worst_weighted = std::max(worst_weighted, report.fit.relative_error[c]);
        most_iterations = std::max(most_iterations, report.fit.iterations[c]);
    }
    m.emplace_back("fit_samples", std::to_string(report.fit.samples));
    m.emplace_back("fit_iterations", std::to_string(most_iterations));
    m.emplace_back("fit_weighted_error_max", number_text(worst_weighted));
    m.emplace_back("fit_invalid_values", std::to_string(report.fit.invalid_values));
}

void record_errors(Metadata& m, const ConvertSettings& settings, const ConvertReport& report) {
    if (settings.error_pairs > 0) {
        m.emplace_back(npf_exr::kMetaFittedErrorMean, number_text(report.fitted_error.mean_relative_rms));
        m.emplace_back(npf_exr::kMetaFittedErrorMax, number_text(report.fitted_error.max_relative_rms));
        m.emplace_back(npf_exr::kMetaErrorMean, number_text(report.compressed_error.mean_relative_rms));
        m.emplace_back(npf_exr::kMetaErrorMax, number_text(report.compressed_error.max_relative_rms));
        const BrdfComparisonResult::Worst& w = report.held_out.worst;
        m.emplace_back("error_held_out_rel_rms", number_text(report.held_out.relative_rms));
        m.emplace_back("error_held_out_rel_rms_60", number_text(report.held_out.relative_rms_60));
        m.emplace_back("error_held_out_largest", number_text(w.test) + " against " + number_text(w.reference) + " (" +
                                                     report.channels.name(w.channel) + ") at pair " +
                                                     std::to_string(w.pair + 1) + " of " +
                                                     std::to_string(report.held_out.pairs));
    }
}

void record_detail(Metadata& m, const NpfModel& model, const ConvertSettings& settings, const ConvertReport& report) {
    m.emplace_back("horizon_closed", settings.close_horizon ? std::to_string(report.horizon_columns_closed) + " columns" : "no");
    if (report.detail_not_kept) {
        m.emplace_back("detail_not_kept", "held-out relative RMS of f_r cos " + number_text(report.detail_not_kept_held_out_rms) +
                                              " with it, " + number_text(report.held_out.relative_rms) + " without");
    }
    if (report.has_detail) {
        m.emplace_back("detail_rank", std::to_string(model.detail.rank));
        m.emplace_back("detail_weighted_error_before", number_text(report.detail.weighted_error_before));
        m.emplace_back("detail_weighted_error_after", number_text(report.detail.weighted_error_after));
        m.emplace_back("detail_energy_error_before", number_text(report.detail.energy_error_before));
        m.emplace_back("detail_energy_error_after", number_text(report.detail.energy_error_after));
        if (settings.error_pairs > 0) {
            m.emplace_back("error_detailed_rel_rms_mean", number_text(report.detailed_error.mean_relative_rms));
            m.emplace_back("error_detailed_rel_rms_max", number_text(report.detailed_error.max_relative_rms));
        }
    }
}

void record_energy(Metadata& m, const ConvertReport& report) {
    m.emplace_back(npf_exr::kMetaAlbedoMax, number_text(report.albedo_max));
    m.emplace_back(npf_exr::kMetaAlbedoMaxViewTheta, number_text(report.albedo_max_theta_deg));
    {
        std::string views;
        for (double v : energy_error_views_deg()) views += (views.empty() ? "" : ",") + number_text(v);
        m.emplace_back("energy_error", number_text(report.energy_error));
        m.emplace_back("energy_error_view_theta", number_text(report.energy_error_theta_deg));
        m.emplace_back("energy_error_channel", report.channels.name(report.energy_error_channel));
        m.emplace_back("energy_error_views", views);
    }
}

void record_prediction(Metadata& m, const ConvertReport& report) {
    // The file's own size is not known before it is written; the source's is.
    if (report.input_bytes > 0) m.emplace_back("source_bytes", std::to_string(report.input_bytes));
    if (report.predicted) {
        m.emplace_back("predicted_psnr", number_text(report.prediction.psnr));
        if (report.prediction.floor_psnr != 0.0) m.emplace_back("predicted_psnr_floor", number_text(report.prediction.floor_psnr));
        m.emplace_back("predicted_psnr_render", report.prediction_settings);
        // A set: each lighting's figures too (predicted_psnr is the worst of them).
        if (report.prediction.lightings.size() > 1) {
            for (const LightingPrediction& l : report.prediction.lightings) {
                m.emplace_back("predicted_psnr_" + l.lighting, number_text(l.psnr));
                if (l.floor_psnr != 0.0) m.emplace_back("predicted_psnr_" + l.lighting + "_floor", number_text(l.floor_psnr));
            }
        }
    }
}

void record_target(Metadata& m, const ConvertSettings& settings, const ConvertReport& report) {
    if (settings.target_psnr != 0.0) {
        std::string tried;
        for (const ConvertReport::TargetCandidate& c : report.target_candidates) {
            tried += (tried.empty() ? "" : " ") + grid_text(c.grid) + ":" + number_text(c.psnr);
        }
        m.emplace_back("target_psnr", number_text(settings.target_psnr));
        m.emplace_back("target_psnr_met", report.target_met ? "true" : "false");
        m.emplace_back("target_psnr_reached", number_text(report.prediction.psnr));
        m.emplace_back("target_psnr_candidates", tried);
    }
}

}  // namespace

void record_conversion(NpfModel& model, const BrdfInfo& info, const ConvertSettings& settings, const AwlsOptions& fit,
                       const CompressionOptions& compression, const ConvertReport& report) {
    Metadata& m = model.metadata;
    record_source(m, info);
    record_settings(m, settings, fit, model.detail_grid);
    record_fit(m, report);
    record_errors(m, settings, report);
    record_detail(m, model, settings, report);
    record_energy(m, report);
    record_prediction(m, report);
    record_target(m, settings, report);
    m.emplace_back("pca_d_ratio_requested", number_text(compression.d_ratio));
    m.emplace_back("pca_g_ratio_requested", number_text(compression.g_ratio));
}

}  // namespace npf
