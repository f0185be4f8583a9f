#include "tables.h"

#include <npf/core/number_text.h>
#include <npf/color/rgb_sigmoid.h>
#include <npf/color/spectrum.h>
#include <npf/fit/npf_factors.h>
#include <npf/fit/spectral_compression.h>
#include <npf/core/vec.h>
#include <npf/shading/npf_equation.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace npf::edit::detail {

Tables expand(const SpectralBasis& basis, std::size_t channels) {
    Tables t;
    t.channels = channels;
    t.cells = basis.cells;
    t.v.assign(channels * basis.cells, 0.0);
    const std::size_t rank = std::size_t(basis.rank);
    for (std::size_t c = 0; c < channels; ++c) {
        double* out = t.row(c);
        for (std::size_t k = 0; k < rank; ++k) {
            const double w = basis.weights[c * rank + k];
            const float* u = basis.basis.data() + k * basis.cells;
            for (std::size_t i = 0; i < basis.cells; ++i) out[i] += w * double(u[i]);
        }
    }
    return t;
}

NpfFactors factors_of(const NpfModel& model, const Tables& d, int d_phi, const Tables& g, int g_phi) {
    NpfFactors f;
    f.grid = RusinkiewiczGrid{model.d_theta, d_phi, model.f_theta, 1};
    f.g_theta = model.g_theta;
    f.g_phi = g_phi;
    f.channels = model.channels;
    f.rho_d = model.rho_d;
    f.rho_s = model.rho_s;
    f.F = model.F;
    f.D.resize(d.v.size());
    f.G.resize(g.v.size());
    std::transform(d.v.begin(), d.v.end(), f.D.begin(), [](double x) { return float(x); });
    std::transform(g.v.begin(), g.v.end(), f.G.begin(), [](double x) { return float(x); });
    return f;
}

NpfModel recompress(const NpfModel& model, const Tables& d, int d_phi, const Tables& g, int g_phi, const NpfModel& like,
                    Recompress how) {
    const NpfFactors f = factors_of(model, d, d_phi, g, g_phi);
    CompressionOptions o;
    if (how == Recompress::KeepRank) {
        o.d_rank = like.D.rank;
        o.g_rank = like.G.rank;
    } else {
        o.d_ratio = like.D.kept_ratio > 0.0 ? std::min(1.0, like.D.kept_ratio) : 1.0;
        o.g_ratio = like.G.kept_ratio > 0.0 ? std::min(1.0, like.G.kept_ratio) : 1.0;
    }
    NpfModel out = compress_factors(f, o);
    out.metadata = model.metadata;
    return out;
}

void drop_detail(NpfModel& model, EditRecord* record, const std::string& why) {
    if (!model.has_detail()) return;
    model.detail_grid = DetailGrid{};
    model.detail = SpectralBasis{};
    warn(record, "the detail layer was dropped: " + why + " (convert the measurement again for a detail layer)");
}

std::vector<double> projected_areas(const Tables& d, int d_theta, int d_phi) {
    std::vector<double> cell(std::size_t(d_theta) * std::size_t(d_phi));
    const double du = 1.0 / d_theta, dphi = 2.0 * kPiD / d_phi;
    for (int i = 0; i < d_theta; ++i) {
        const double u = (i + 0.5) * du, th = equation::theta_h_of_u(u);
        const double w = std::cos(th) * std::sin(th) * kPiD * u * du * dphi;
        for (int j = 0; j < d_phi; ++j) cell[std::size_t(i) * std::size_t(d_phi) + std::size_t(j)] = w;
    }
    std::vector<double> area(d.channels, 0.0);
    for (std::size_t c = 0; c < d.channels; ++c) {
        const double* t = d.row(c);
        double a = 0.0;
        for (std::size_t i = 0; i < d.cells; ++i) a += std::max(0.0, t[i]) * cell[i];
        area[c] = a;
    }
    return area;
}

void warn(EditRecord* record, const std::string& text) {
    if (record) record->warnings.push_back(text);
}

std::vector<double> convert_channels(const Channels& from, const std::vector<double>& values, const Channels& to,
                                     const std::string& what, EditRecord* record) {
    if (from.is_rgb() && to.is_rgb()) return values;
    if (!from.is_rgb() && !to.is_rgb()) {
        if (from.wavelengths() == to.wavelengths()) return values;
        const std::vector<float>& fw = from.wavelengths();
        const std::vector<float>& tw = to.wavelengths();
        if (tw.front() < fw.front() - 5.f || tw.back() > fw.back() + 5.f) {
            warn(record, what + ": the source covers " + number_text(fw.front(), 5) + " to " + number_text(fw.back(), 5) +
                             " nm, the material " + number_text(tw.front(), 5) + " to " + number_text(tw.back(), 5) +
                             " nm; held constant beyond the source's range");
        }
        const color::SampledSpectrum s(std::vector<double>(fw.begin(), fw.end()), values);
        return s.sample(tw);
    }
    if (to.is_rgb()) {
        const auto w = color::linear_srgb_weights(from.wavelengths());
        std::vector<double> rgb(3, 0.0);
        bool clamped = false;
        for (int k = 0; k < 3; ++k) {
            double v = 0.0;
            for (std::size_t i = 0; i < values.size(); ++i) v += w[std::size_t(k)][i] * values[i];
            if (v < 0.0) v = 0.0, clamped = true;
            rgb[std::size_t(k)] = v;
        }
        if (clamped) warn(record, what + ": the spectrum's colour lies outside the sRGB gamut; negative components set to 0");
        return rgb;
    }
    // RGB to spectral.
    const color::Rgb rgb{std::max(0.0, values[0]), std::max(0.0, values[1]), std::max(0.0, values[2])};
    if (values[0] < 0.0 || values[1] < 0.0 || values[2] < 0.0) warn(record, what + ": negative RGB components taken as 0");
    std::vector<double> out;
    out.reserve(to.size());
    const double top = std::max({rgb[0], rgb[1], rgb[2]});
    if (top <= 1.0) {
        const color::RgbSigmoid s = color::rgb_to_sigmoid(rgb, color::SigmoidFit::Refined);
        for (float l : to.wavelengths()) out.push_back(s(l));
    } else {
        const color::RgbUnboundedSpectrum s(rgb, color::SigmoidFit::Refined);
        for (float l : to.wavelengths()) out.push_back(s(l));
    }
    return out;
}

}  // namespace npf::edit::detail
