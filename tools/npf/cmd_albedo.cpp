// npf albedo MATERIAL [--against REFERENCE]: the directional albedo a(wi) per view angle, and
// with a reference, where and by how much the two differ (docs/albedo.md). The main use is a
// fitted texture against its source: `npf albedo fitted.npf.exr --against source.bsdf`.
#include "command_line.h"

#include <npf/core/number_text.h>
#include "commands.h"

#include <npf/color/spectrum.h>
#include <npf/materials/open_material.h>
#include <npf/core/directional_albedo.h>
#include <npf/core/error.h>
#include <npf/core/json_text.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = {
    {"--against", true, "a reference material: print both and (MATERIAL - REFERENCE) / REFERENCE per channel"},
    {"--theta", true, "view angles in degrees, each in [0, 90): '0,45,89' or 'start:end:count' "
                      "(default 0,10,...,80,85,87,89)"},
    {"--azimuths", true, "N view azimuths evenly spread from 0 degrees (default 1 for isotropic materials, 4 if "
                         "either is anisotropic)"},
    {"--samples", true, "N: N x N cells per estimator strategy, 2..4096 (default 128: errors of about 0.1 %)"},
    {"--monte-carlo", false, "factor textures too: the Monte Carlo estimator instead of their quadrature (a cross-check)"},
    {"--wavelengths", true, "spectral files: evaluate at '450,550,650' or 'start:end:count' (nm)"},
    {"--json", false, "print one JSON object instead of the table"},
    {"--help", false, "show this help"},
};

const char* kHelp =
    "usage: npf albedo MATERIAL [--against REFERENCE] [--theta LIST] [--azimuths N] [--samples N]\n"
    "                  [--monte-carlo] [--wavelengths LIST] [--json]\n\n"
    "Directional albedo a(wi) = integral of f_r(wi, wo) cos(theta_o) over the hemisphere: the share\n"
    "of light from the view direction wi (theta from the normal, phi from the tangent) that the\n"
    "material reflects. Any material npf opens: RGL .bsdf, MERL .binary, NPF .exr, .yaml recipes.\n"
    "One row per view direction (anisotropic materials: one per azimuth, phi, too); columns are the\n"
    "channels (R G B, or the wavelengths in nm; more than six wavelengths are summarised as Y, the\n"
    "CIE-luminance-weighted mean, and min and max).\n"
    "With --against, both materials are evaluated at the reference's channels (at the material's when\n"
    "the reference is a recipe and the material cannot answer them) and the last columns are\n"
    "(MATERIAL - REFERENCE) / REFERENCE in percent; a final line names the worst difference and its\n"
    "standard error.\n"
    "Estimator (the one every npf report uses, docs/albedo.md): a factor texture is integrated by a\n"
    "quadrature on its own tables (within about 0.2 %, no sampling error); any other material by Monte\n"
    "Carlo: its own sampler and cosine-weighted directions, one of each in every cell of an N x N grid,\n"
    "combined by multiple importance sampling. Both are deterministic.\n\n";

constexpr std::size_t kMaxChannelColumns = 6;

std::string format(const char* fmt, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, fmt, v);
    return buf;
}

std::string json_array(const std::vector<double>& v) {
    std::string out = "[";
    for (std::size_t k = 0; k < v.size(); ++k) out += (k ? ", " : "") + json_number(v[k]);
    return out + "]";
}

bool parse_double(const std::string& text, double& v) {
    try {
        v = parse_finite_number(text, "");
        return true;
    } catch (const Error&) {
        return false;
    }
}

// "0,45,89" or "start:end:count" (count evenly spaced values, both ends included).
std::vector<double> parse_theta_list(const std::string& text) {
    const auto bad = [&](const std::string& why) { return Error("--theta", "'" + text + "': " + why); };
    std::vector<double> out;
    if (text.find(':') != std::string::npos) {
        const std::size_t a = text.find(':'), b = text.find(':', a + 1);
        double start = 0, end = 0, count = 0;
        if (b == std::string::npos || text.find(':', b + 1) != std::string::npos ||
            !parse_double(text.substr(0, a), start) || !parse_double(text.substr(a + 1, b - a - 1), end) ||
            !parse_double(text.substr(b + 1), count) || count != std::floor(count) || count < 1 || count > 10000)
            throw bad("expected 'start:end:count' with a whole count in 1..10000");
        if (count == 1 && start != end) throw bad("a count of 1 needs start = end");
        for (int k = 0; k < int(count); ++k) out.push_back(count == 1 ? start : start + (end - start) * k / (count - 1));
    } else {
        std::size_t pos = 0;
        while (true) {
            const std::size_t comma = text.find(',', pos);
            const std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
            double v = 0;
            if (!parse_double(item, v)) throw bad("'" + item + "' is not a number");
            out.push_back(v);
            if (comma == std::string::npos) break;
            pos = comma + 1;
        }
    }
    for (double v : out) {
        if (!(v >= 0.0 && v < 90.0))
            throw Error("--theta", format("%g", v) + " is outside [0, 90) degrees (90 is the horizon: no albedo there)");
    }
    return out;
}

// Channel names for headers and the worst-difference line.
std::vector<std::string> channel_names(const Channels& channels) {
    std::vector<std::string> names;
    for (std::size_t c = 0; c < channels.size(); ++c) names.push_back(channels.name(c));
    return names;
}

// Weights of the Y summary of a long spectral list: CIE Y, normalised to sum 1 (a plain mean when
// the list lies outside the visible range). The list may be in any order.
std::vector<double> summary_weights(const std::vector<float>& wavelengths) {
    std::vector<std::size_t> order(wavelengths.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return wavelengths[a] < wavelengths[b]; });
    std::vector<float> sorted;
    for (std::size_t k : order) sorted.push_back(wavelengths[k]);
    const std::vector<double> y = color::luminance_weights(sorted);
    std::vector<double> w(wavelengths.size(), 0.0);
    double total = 0.0;
    for (std::size_t k = 0; k < order.size(); ++k) {
        w[order[k]] = y[k];
        total += y[k];
    }
    for (double& v : w) v = total > 0.0 ? v / total : 1.0 / double(w.size());
    return w;
}

std::string percent(double rel) {
    if (std::isnan(rel)) return "nan";
    if (std::isinf(rel)) return rel > 0 ? "+inf" : "-inf";
    return format("%+.2f%%", 100.0 * rel);
}

std::string describe_material(const std::string& path, const Brdf& brdf) {
    const BrdfInfo& info = brdf.info();
    return path + " (" + info.format + ", " + (info.isotropic ? "isotropic" : "anisotropic") + ")";
}

}  // namespace

int run_albedo(const std::vector<std::string>& args) {
    CommandLine cl("albedo", args, kFlags);
    if (cl.has("--help")) {
        std::printf("%s%s", kHelp, usage_lines(kFlags).c_str());
        return 0;
    }
    cl.expect_positional(1, 1, "one MATERIAL");
    // Options first, so that a bad flag fails before any file is read.
    AlbedoTableOptions options;
    if (cl.has("--theta")) options.theta_deg = parse_theta_list(cl.value("--theta"));
    options.estimator.samples = int(cl.whole("--samples", 2, 4096, std::uint64_t(options.estimator.samples)));
    options.estimator.material_quadrature = !cl.has("--monte-carlo");
    const int azimuth_count = int(cl.whole("--azimuths", 1, 360, 0));
    std::vector<float> wavelengths;
    if (cl.has("--wavelengths")) wavelengths = parse_wavelength_list(cl.value("--wavelengths"), "--wavelengths");

    const std::string material_path = cl.positional()[0];
    const bool against = cl.has("--against");
    const std::string reference_path = cl.value("--against");
    const std::unique_ptr<Brdf> material = open_material(material_path);
    const std::unique_ptr<Brdf> reference = against ? open_material(reference_path) : nullptr;

    // Channels: the reference's own (or the material's), so that a comparison reads the source as
    // stored and asks the material for the same channels.
    const Brdf& channel_source = against ? *reference : *material;
    const std::string& channel_source_path = against ? reference_path : material_path;
    Channels channels = channel_source.info().channels;
    if (!wavelengths.empty()) {
        if (channels.is_rgb()) throw Error(channel_source_path, "holds RGB data; --wavelengths needs a spectral file");
        channels = Channels::spectral(wavelengths);
    }
    ChannelQuery material_query, reference_query;
    try {
        material_query = material->query(channels);
        if (against) reference_query = reference->query(channels);
    } catch (const Error& e) {
        // An RGB material against a reference that computes any channel (an analytic recipe):
        // compare in the material's channels instead. Otherwise the channels do not match.
        if (!against || !wavelengths.empty()) throw;
        try {
            channels = material->info().channels;
            material_query = material->query(channels);
            reference_query = reference->query(channels);
        } catch (const Error&) {
            throw Error(material_path, "cannot be compared with " + reference_path + ": " + e.problem());
        }
    }

    const bool isotropic = material->info().isotropic && (!against || reference->info().isotropic);
    if (azimuth_count > 0) {
        for (int k = 0; k < azimuth_count; ++k) options.phi_deg.push_back(360.0 * k / azimuth_count);
    } else {
        options.phi_deg = default_albedo_azimuths(isotropic);
    }

    const std::vector<AlbedoRow> rows = directional_albedo_table(*material, material_query, options);
    const std::vector<AlbedoRow> reference_rows =
        against ? directional_albedo_table(*reference, reference_query, options) : std::vector<AlbedoRow>();

    // An albedo that is not a finite number is the material's fault (values that overflow the
    // estimator's sums), never a result to print as null with exit 0.
    auto require_finite = [](const std::vector<AlbedoRow>& table, const std::string& path) {
        for (const AlbedoRow& row : table) {
            for (double a : row.albedo) {
                if (!std::isfinite(a)) {
                    throw Error(path, "its directional albedo at " + json_number(row.theta_deg) +
                                          " degrees is not a finite number (its values overflow)");
                }
            }
        }
    };
    require_finite(rows, material_path);
    require_finite(reference_rows, reference_path);

    const std::size_t n = channels.size();
    const std::vector<std::string> names = channel_names(channels);
    std::vector<std::vector<double>> relative(rows.size());
    for (std::size_t r = 0; r < reference_rows.size(); ++r)
        for (std::size_t c = 0; c < n; ++c) relative[r].push_back(relative_albedo_difference(rows[r].albedo[c], reference_rows[r].albedo[c]));
    const AlbedoDifference largest = largest_albedo_difference(rows, reference_rows);
    const std::size_t worst_row = largest.row, worst_channel = largest.channel;
    double worst = 0.0, worst_se = 0.0, worst_material = 0.0, worst_reference = 0.0;
    if (against) {
        worst = relative[worst_row][worst_channel];
        worst_material = rows[worst_row].albedo[worst_channel];
        worst_reference = reference_rows[worst_row].albedo[worst_channel];
        // The standard error of the ratio, to first order: is the worst difference significant?
        const double sm = rows[worst_row].standard_error[worst_channel];
        const double sr = reference_rows[worst_row].standard_error[worst_channel];
        worst_se = worst_reference > 0.0
                       ? std::hypot(sm / worst_reference, worst_material * sr / (worst_reference * worst_reference))
                       : NAN;
    }
    const bool with_phi = options.phi_deg.size() != 1 || options.phi_deg[0] != 0.0;

    if (cl.has("--json")) {
        std::string out = "{\"material\": " + json_string(material_path);
        if (against) out += ", \"reference\": " + json_string(reference_path);
        out += ", \"channels\": [";
        for (std::size_t c = 0; c < n; ++c) {
            if (c) out += ", ";
            out += channels.is_rgb() ? json_string(names[c]) : json_number(channels.wavelengths()[c]);
        }
        out += "], \"samples\": " + std::to_string(options.estimator.samples);
        out += ", \"columns\": [\"theta_deg\", \"phi_deg\", \"albedo\", \"albedo_se\"";
        if (against) out += ", \"reference\", \"reference_se\", \"relative_difference\"";
        out += "], \"rows\": [";
        for (std::size_t r = 0; r < rows.size(); ++r) {
            out += r ? ", [" : "[";
            out += json_number(rows[r].theta_deg) + ", " + json_number(rows[r].phi_deg) + ", " +
                   json_array(rows[r].albedo) + ", " + json_array(rows[r].standard_error);
            if (against)
                out += ", " + json_array(reference_rows[r].albedo) + ", " + json_array(reference_rows[r].standard_error) +
                       ", " + json_array(relative[r]);
            out += "]";
        }
        out += "]";
        if (against) {
            out += ", \"worst\": {\"relative_difference\": " + json_number(worst) +
                   ", \"standard_error\": " + json_number(worst_se) +
                   ", \"theta_deg\": " + json_number(rows[worst_row].theta_deg) +
                   ", \"phi_deg\": " + json_number(rows[worst_row].phi_deg) + ", \"channel\": " +
                   (channels.is_rgb() ? json_string(names[worst_channel])
                                      : json_number(channels.wavelengths()[worst_channel])) +
                   "}";
        }
        out += "}\n";
        std::fwrite(out.data(), 1, out.size(), stdout);
        return 0;
    }

    // Text: a few comment lines, a header, one row per direction.
    const bool summary = n > kMaxChannelColumns;
    const std::vector<double> y_weights = summary ? summary_weights(channels.wavelengths()) : std::vector<double>();
    double largest_se = 0.0;
    auto track_se = [&](const std::vector<AlbedoRow>& rs) {
        for (const AlbedoRow& row : rs) {
            for (std::size_t c = 0; c < n; ++c) {
                if (row.albedo[c] > 0.0) largest_se = std::max(largest_se, row.standard_error[c] / row.albedo[c]);
            }
        }
    };
    track_se(rows);
    track_se(reference_rows);

    std::string out = "# directional albedo a(wi) = integral f_r cos(theta_o) d(wo); view angles in degrees\n";
    out += "# material:  " + describe_material(material_path, *material) + "\n";
    if (against) out += "# reference: " + describe_material(reference_path, *reference) + "\n";
    out += "# channels:  " + (summary ? std::to_string(n) + " wavelengths " + format("%g", channels.wavelengths().front()) +
                                            " .. " + format("%g", channels.wavelengths().back()) +
                                            " nm (Y: CIE-luminance-weighted mean, min, max over them)"
                                      : channels.describe() + (channels.is_rgb() ? "" : " nm")) + "\n";
    const std::string monte_carlo = std::to_string(options.estimator.samples) + " x " +
                                    std::to_string(options.estimator.samples) + " cells, material sampler + cosine (MIS)";
    auto estimator_of = [&](const std::vector<AlbedoRow>& rs) {
        return !rs.empty() && rs[0].by_quadrature ? std::string("quadrature on the factor tables") : monte_carlo;
    };
    const std::string material_estimator = estimator_of(rows);
    if (!against || estimator_of(reference_rows) == material_estimator) {
        out += "# estimator: " + material_estimator;
    } else {
        out += "# estimator: material " + material_estimator + "; reference " + estimator_of(reference_rows);
    }
    out += "; largest relative standard error " + format("%.2g", 100.0 * largest_se) + " %\n";

    // The table as cells first, then every column right-aligned to its widest cell; "|"
    // separates the material, the reference and the differences.
    const std::vector<std::string> value_names = summary ? std::vector<std::string>{"Y", "min", "max"} : names;
    auto values_of = [&](const std::vector<double>& a) {
        if (!summary) return a;
        double y = 0.0;
        for (std::size_t c = 0; c < n; ++c) y += y_weights[c] * a[c];
        return std::vector<double>{y, *std::min_element(a.begin(), a.end()), *std::max_element(a.begin(), a.end())};
    };
    std::vector<std::vector<std::string>> table;
    std::vector<std::string> header = {"theta"};
    if (with_phi) header.push_back("phi");
    for (const std::string& s : value_names) header.push_back(s);
    if (against) {
        header.push_back("|");
        for (const std::string& s : value_names) header.push_back("ref " + s);
        header.push_back("|");
        if (summary) {
            for (const char* s : {"diff Y", "worst", "at"}) header.push_back(s);
        } else {
            for (const std::string& s : names) header.push_back("diff " + s);
        }
    }
    table.push_back(header);
    for (std::size_t r = 0; r < rows.size(); ++r) {
        std::vector<std::string> line = {format("%g", rows[r].theta_deg)};
        if (with_phi) line.push_back(format("%g", rows[r].phi_deg));
        const std::vector<double> mine = values_of(rows[r].albedo);
        for (double v : mine) line.push_back(format("%.5f", v));
        if (against) {
            line.push_back("|");
            const std::vector<double> theirs = values_of(reference_rows[r].albedo);
            for (double v : theirs) line.push_back(format("%.5f", v));
            line.push_back("|");
            if (summary) {
                std::size_t k = 0;
                for (std::size_t c = 1; c < n; ++c) {
                    if (std::fabs(relative[r][c]) > std::fabs(relative[r][k])) k = c;
                }
                line.push_back(percent(relative_albedo_difference(mine[0], theirs[0])));
                line.push_back(percent(relative[r][k]));
                line.push_back(names[k]);
            } else {
                for (double d : relative[r]) line.push_back(percent(d));
            }
        }
        table.push_back(line);
    }
    std::vector<std::size_t> width(header.size(), 0);
    for (const auto& line : table) {
        for (std::size_t k = 0; k < line.size(); ++k) width[k] = std::max(width[k], line[k].size());
    }
    for (const auto& line : table) {
        std::string text;
        for (std::size_t k = 0; k < line.size(); ++k) {
            if (k) text += "  ";
            text += std::string(width[k] - line[k].size(), ' ') + line[k];
        }
        out += text + "\n";
    }
    if (against) {
        out += "worst relative difference: " + percent(worst) + " +- " + format("%.2f%%", 100.0 * worst_se) + " (" +
               names[worst_channel] + ") at theta " + format("%g", rows[worst_row].theta_deg) +
               (with_phi ? ", phi " + format("%g", rows[worst_row].phi_deg) : std::string()) + ": material " +
               format("%.5f", worst_material) + ", reference " + format("%.5f", worst_reference) + "\n";
    }
    std::fwrite(out.data(), 1, out.size(), stdout);
    return 0;
}

}  // namespace npf::cli
