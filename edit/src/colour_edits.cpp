#include <npf/edit/colour_edits.h>

#include "tables.h"

#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/core/vec.h>
#include <npf/shading/table_interpolation.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace npf::edit {

namespace {

bool same_channels(const Channels& a, const Channels& b) {
    return a.is_rgb() == b.is_rgb() && (a.is_rgb() || a.wavelengths() == b.wavelengths());
}

void check_scale(double scale, const char* what) {
    if (!std::isfinite(scale) || scale < 0.0) {
        throw Error(what, "scale " + number_text(scale) + " must be a finite number >= 0");
    }
}

// The colour of per-channel values as text: RGB as stored, spectra as their linear sRGB colour.
std::string colour_text(const Channels& ch, const std::vector<double>& v) {
    std::vector<double> rgb = v;
    if (!ch.is_rgb()) {
        const auto w = color::linear_srgb_weights(ch.wavelengths());
        rgb.assign(3, 0.0);
        for (int k = 0; k < 3; ++k) {
            for (std::size_t i = 0; i < v.size(); ++i) rgb[std::size_t(k)] += w[std::size_t(k)][i] * v[i];
        }
    }
    return std::string(ch.is_rgb() ? "" : "colour ") + "(" + number_text(rgb[0], 4) + ", " + number_text(rgb[1], 4) + ", " +
           number_text(rgb[2], 4) + ")";
}

// CIE Y of per-channel values (linear sRGB luminance for RGB).
double luminance(const Channels& ch, const std::vector<double>& v) {
    if (ch.is_rgb()) return color::linear_srgb_luminance({v[0], v[1], v[2]});
    const std::vector<double> w = color::luminance_weights(ch.wavelengths());
    double y = 0.0;
    for (std::size_t i = 0; i < v.size(); ++i) y += w[i] * v[i];
    return y;
}

std::vector<double> albedo_of(const std::vector<float>& rho_d) {
    std::vector<double> a(rho_d.size());
    for (std::size_t c = 0; c < a.size(); ++c) a[c] = kPiD * rho_d[c];
    return a;
}

NpfModel with_albedo(const NpfModel& model, const std::vector<double>& albedo, const std::string& what, EditRecord* record) {
    NpfModel out = model;
    bool above_one = false;
    for (std::size_t c = 0; c < albedo.size(); ++c) {
        if (!std::isfinite(albedo[c]) || albedo[c] < 0.0) {
            throw Error("diffuse edit", "albedo " + number_text(albedo[c]) + " in channel " + std::to_string(c) +
                                            " is not a finite number >= 0");
        }
        above_one = above_one || albedo[c] > 1.0;
        out.rho_d[c] = float(albedo[c] / kPiD);
    }
    if (record) {
        record->summary = "diffuse " + what + ": albedo pi rho_d " + colour_text(model.channels, albedo_of(model.rho_d)) +
                          " -> " + colour_text(model.channels, albedo_of(out.rho_d));
        if (above_one) detail::warn(record, "the new diffuse albedo exceeds 1 in some channel");
    }
    out.validate("diffuse edit");
    return out;
}

void merge_unique(EditRecord* record, const EditRecord& from) {
    if (!record) return;
    for (const std::string& w : from.warnings) {
        if (std::find(record->warnings.begin(), record->warnings.end(), w) == record->warnings.end()) {
            record->warnings.push_back(w);
        }
    }
}

}  // namespace

NpfModel replace_diffuse(const NpfModel& model, const NpfModel& from, double scale, EditRecord* record) {
    check_scale(scale, "diffuse edit");
    if (same_channels(model.channels, from.channels)) {
        NpfModel out = model;
        for (std::size_t c = 0; c < out.rho_d.size(); ++c) out.rho_d[c] = scale == 1.0 ? from.rho_d[c] : float(from.rho_d[c] * scale);
        if (record) {
            record->summary = "diffuse from another material (scale " + number_text(scale) + "): albedo pi rho_d " +
                              colour_text(model.channels, albedo_of(model.rho_d)) + " -> " +
                              colour_text(model.channels, albedo_of(out.rho_d));
        }
        out.validate("diffuse edit");
        return out;
    }
    EditRecord notes;
    std::vector<double> albedo = detail::convert_channels(from.channels, albedo_of(from.rho_d), model.channels,
                                                          "diffuse colour", &notes);
    for (double& a : albedo) a *= scale;
    NpfModel out = with_albedo(model, albedo,
                               "from another material (" + std::string(from.channels.is_rgb() ? "RGB" : "spectral") +
                                   " into " + (model.channels.is_rgb() ? "RGB" : "spectral") + ", scale " + number_text(scale) + ")",
                               record);
    merge_unique(record, notes);
    return out;
}

NpfModel replace_diffuse_albedo(const NpfModel& model, const color::SampledSpectrum& albedo, EditRecord* record) {
    if (albedo.empty()) throw Error("diffuse edit", "the albedo spectrum is empty");
    for (double v : albedo.values()) {
        if (!std::isfinite(v) || v < 0.0) throw Error("diffuse edit", "albedo spectrum value " + number_text(v) + " is not >= 0");
    }
    std::vector<double> a;
    if (model.channels.is_rgb()) {
        const color::Rgb rgb = color::xyz_to_linear_srgb(color::spectrum_to_xyz(albedo));
        bool clamped = false;
        for (double v : rgb) {
            clamped = clamped || v < 0.0;
            a.push_back(std::max(0.0, v));
        }
        if (clamped && record) detail::warn(record, "the spectrum's colour lies outside the sRGB gamut; negative components set to 0");
    } else {
        a = albedo.sample(model.channels.wavelengths());
    }
    return with_albedo(model, a, "albedo from a spectrum", record);
}

NpfModel replace_diffuse_albedo(const NpfModel& model, const color::Rgb& linear_albedo, EditRecord* record) {
    for (double v : linear_albedo) {
        if (!std::isfinite(v) || v < 0.0) throw Error("diffuse edit", "colour component " + number_text(v) + " is not >= 0");
    }
    EditRecord notes;
    const std::vector<double> a = detail::convert_channels(Channels::rgb(), {linear_albedo[0], linear_albedo[1], linear_albedo[2]},
                                                           model.channels, "diffuse colour", &notes);
    NpfModel out = with_albedo(model, a,
                               "albedo from the linear sRGB colour (" + number_text(linear_albedo[0], 4) + ", " +
                                   number_text(linear_albedo[1], 4) + ", " + number_text(linear_albedo[2], 4) + ")" +
                                   (model.channels.is_rgb() ? "" : ", upsampled"),
                               record);
    merge_unique(record, notes);
    return out;
}

NpfModel replace_specular(const NpfModel& model, const NpfModel& from, const SpecularSwap& swap, EditRecord* record) {
    const double scale = swap.scale;
    check_scale(scale, "specular edit");
    NpfModel out = model;
    const std::size_t C = model.channel_count();
    const std::vector<double> k0_before = [&] {
        std::vector<double> k(C);
        for (std::size_t c = 0; c < C; ++c) k[c] = double(model.rho_s[c]) * model.F[c * std::size_t(model.f_theta)];
        return k;
    }();
    EditRecord notes;
    if (same_channels(model.channels, from.channels) && model.f_theta == from.f_theta) {
        for (std::size_t c = 0; c < C; ++c) out.rho_s[c] = scale == 1.0 ? from.rho_s[c] : float(from.rho_s[c] * scale);
        out.F = from.F;
    } else {
        // K(theta_d) = rho_s F(theta_d) of the source at the model's theta_d centres, moved to the
        // model's channels row by row, then split again into rho_s and F in the gauge.
        const int n = model.f_theta;
        const std::size_t Cs = from.channel_count();
        std::vector<std::vector<double>> rows(static_cast<std::size_t>(n));
        for (int k = 0; k < n; ++k) {
            const double theta_d = 0.5 * kPiD * (k + 0.5) / n;
            const table::Lerp l = table::clamped(theta_d / (0.5 * kPiD) * from.f_theta, from.f_theta);
            std::vector<double> ks(Cs);
            for (std::size_t c = 0; c < Cs; ++c) {
                const float* f = from.F.data() + c * std::size_t(from.f_theta);
                ks[c] = double(from.rho_s[c]) * (f[l.i0] * (1.0 - l.t) + f[l.i1] * l.t);
            }
            rows[std::size_t(k)] = detail::convert_channels(from.channels, ks, model.channels, "specular colour", &notes);
        }
        for (std::size_t c = 0; c < C; ++c) {
            const double k0 = rows[0][c];
            out.rho_s[c] = float(k0 * scale);
            for (int k = 0; k < n; ++k) {
                out.F[c * std::size_t(n) + std::size_t(k)] = k0 > 0.0 ? float(rows[std::size_t(k)][c] / k0) : 1.f;
            }
        }
    }
    double brightness = 1.0;
    if (swap.keep_brightness) {
        std::vector<double> k0_new(C);
        for (std::size_t c = 0; c < C; ++c) k0_new[c] = double(out.rho_s[c]) * out.F[c * std::size_t(out.f_theta)];
        const double y_old = luminance(model.channels, k0_before), y_new = luminance(model.channels, k0_new);
        if (y_new > 0.0 && y_old >= 0.0) {
            brightness = y_old / y_new;
            for (float& r : out.rho_s) r = float(r * brightness);
        }
    }
    if (record) {
        std::vector<double> k0_after(C);
        for (std::size_t c = 0; c < C; ++c) k0_after[c] = double(out.rho_s[c]) * out.F[c * std::size_t(out.f_theta)];
        record->summary = "specular colour rho_s F from another material (" +
                          std::string(from.channels.is_rgb() ? "RGB" : "spectral") + " into " +
                          (model.channels.is_rgb() ? "RGB" : "spectral") + ", scale " + number_text(scale) +
                          (swap.keep_brightness ? ", brightness kept: x " + number_text(brightness, 4) : std::string()) +
                          "): rho_s F at normal incidence " + colour_text(model.channels, k0_before) + " -> " +
                          colour_text(model.channels, k0_after) + "; D and G unchanged";
        merge_unique(record, notes);
    }
    detail::drop_detail(out, record, "the specular colour changed, and the residual was fitted to the old one");
    out.validate("specular edit");
    return out;
}

}  // namespace npf::edit
