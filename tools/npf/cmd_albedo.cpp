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
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = flag_table({
    "--against VALUE  a reference material: print both and (MATERIAL - REFERENCE) / REFERENCE per channel",
    "--theta VALUE  view angles in degrees, each in [0, 90): '0,45,89' or 'start:end:count' "
    "(default 0,10,...,80,85,87,89)",
    "--azimuths VALUE  N view azimuths evenly spread from 0 degrees (default 1 for isotropic materials, 4 if "
    "either is anisotropic)",
    "--samples VALUE  N: N x N cells per estimator strategy, 2..4096 (default 128: errors of about 0.1 %)",
    "--monte-carlo  factor textures too: the Monte Carlo estimator instead of their quadrature (a cross-check)",
    "--wavelengths VALUE  spectral files: evaluate at '450,550,650' or 'start:end:count' (nm)",
    "--json  print one JSON object instead of the table",
});

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

// What --theta, --samples, --monte-carlo, --azimuths and --wavelengths ask for, read before any
// file so that a bad flag fails first.
struct AlbedoRequest {
    AlbedoTableOptions options;
    int azimuth_count = 0;  // 0: the material's default azimuths
    std::vector<float> wavelengths;
};

AlbedoRequest read_request(const CommandLine& cl) {
    AlbedoRequest request;
    AlbedoTableOptions& options = request.options;
    if (cl.has("--theta")) options.theta_deg = parse_theta_list(cl.value("--theta"));
    options.estimator.samples = int(cl.whole("--samples", 2, 4096, std::uint64_t(options.estimator.samples)));
    options.estimator.material_quadrature = !cl.has("--monte-carlo");
    request.azimuth_count = int(cl.whole("--azimuths", 1, 360, 0));
    if (cl.has("--wavelengths")) request.wavelengths = parse_wavelength_list(cl.value("--wavelengths"), "--wavelengths");
    return request;
}

// The material's albedo table and, with --against, the reference's at the same views and channels.
struct Measurement {
    std::string material_path, reference_path;
    std::unique_ptr<Brdf> material, reference;  // reference null without --against
    Channels channels;
    AlbedoTableOptions options;
    std::vector<AlbedoRow> rows, reference_rows;
    bool against() const { return reference != nullptr; }
};

// Channels: the reference's own (or the material's), so that a comparison reads the source as
// stored and asks the material for the same channels. Sets m.channels; returns the two queries.
std::pair<ChannelQuery, ChannelQuery> choose_channels(Measurement& m, const std::vector<float>& wavelengths) {
    const Brdf& channel_source = m.against() ? *m.reference : *m.material;
    const std::string& channel_source_path = m.against() ? m.reference_path : m.material_path;
    m.channels = channel_source.info().channels;
    if (!wavelengths.empty()) {
        if (m.channels.is_rgb()) throw Error(channel_source_path, "holds RGB data; --wavelengths needs a spectral file");
        m.channels = Channels::spectral(wavelengths);
    }
    ChannelQuery material_query, reference_query;
    try {
        material_query = m.material->query(m.channels);
        if (m.against()) reference_query = m.reference->query(m.channels);
    } catch (const Error& e) {
        // An RGB material against a reference that computes any channel (an analytic recipe):
        // compare in the material's channels instead. Otherwise the channels do not match.
        if (!m.against() || !wavelengths.empty()) throw;
        try {
            m.channels = m.material->info().channels;
            material_query = m.material->query(m.channels);
            reference_query = m.reference->query(m.channels);
        } catch (const Error&) {
            throw Error(m.material_path, "cannot be compared with " + m.reference_path + ": " + e.problem());
        }
    }
    return {material_query, reference_query};
}

// An albedo that is not a finite number is the material's fault (values that overflow the
// estimator's sums), never a result to print as null with exit 0.
void require_finite(const std::vector<AlbedoRow>& table, const std::string& path) {
    for (const AlbedoRow& row : table) {
        for (double a : row.albedo) {
            if (!std::isfinite(a)) {
                throw Error(path, "its directional albedo at " + json_number(row.theta_deg) +
                                      " degrees is not a finite number (its values overflow)");
            }
        }
    }
}

Measurement measure(const CommandLine& cl) {
    AlbedoRequest request = read_request(cl);
    Measurement m;
    m.material_path = cl.positional()[0];
    m.reference_path = cl.value("--against");
    m.material = open_material(m.material_path);
    if (cl.has("--against")) m.reference = open_material(m.reference_path);
    const auto [material_query, reference_query] = choose_channels(m, request.wavelengths);

    m.options = std::move(request.options);
    const bool isotropic = m.material->info().isotropic && (!m.against() || m.reference->info().isotropic);
    if (request.azimuth_count > 0) {
        for (int k = 0; k < request.azimuth_count; ++k) m.options.phi_deg.push_back(360.0 * k / request.azimuth_count);
    } else {
        m.options.phi_deg = default_albedo_azimuths(isotropic);
    }
    m.rows = directional_albedo_table(*m.material, material_query, m.options);
    if (m.against()) m.reference_rows = directional_albedo_table(*m.reference, reference_query, m.options);
    require_finite(m.rows, m.material_path);
    require_finite(m.reference_rows, m.reference_path);
    return m;
}

// The material against the reference: per row and channel, and where they differ most.
struct Comparison {
    std::vector<std::vector<double>> relative;  // per row and channel; empty rows without --against
    std::size_t row = 0, channel = 0;           // of the worst difference
    double worst = 0.0, standard_error = 0.0, material = 0.0, reference = 0.0;
};

Comparison compare(const Measurement& m) {
    Comparison c;
    c.relative.resize(m.rows.size());
    if (!m.against()) return c;
    for (std::size_t r = 0; r < m.reference_rows.size(); ++r) {
        for (std::size_t k = 0; k < m.channels.size(); ++k)
            c.relative[r].push_back(relative_albedo_difference(m.rows[r].albedo[k], m.reference_rows[r].albedo[k]));
    }
    const AlbedoDifference largest = largest_albedo_difference(m.rows, m.reference_rows);
    c.row = largest.row;
    c.channel = largest.channel;
    c.worst = c.relative[c.row][c.channel];
    c.material = m.rows[c.row].albedo[c.channel];
    c.reference = m.reference_rows[c.row].albedo[c.channel];
    // The standard error of the ratio, to first order: is the worst difference significant?
    const double sm = m.rows[c.row].standard_error[c.channel];
    const double sr = m.reference_rows[c.row].standard_error[c.channel];
    c.standard_error = c.reference > 0.0 ? std::hypot(sm / c.reference, c.material * sr / (c.reference * c.reference)) : NAN;
    return c;
}

std::string json_channel(const Channels& channels, std::size_t k) {
    return channels.is_rgb() ? json_string(channels.name(k)) : json_number(channels.wavelengths()[k]);
}

std::string json_report(const Measurement& m, const Comparison& c) {
    std::string out = "{\"material\": " + json_string(m.material_path);
    if (m.against()) out += ", \"reference\": " + json_string(m.reference_path);
    out += ", \"channels\": [";
    for (std::size_t k = 0; k < m.channels.size(); ++k) out += (k ? ", " : "") + json_channel(m.channels, k);
    out += "], \"samples\": " + std::to_string(m.options.estimator.samples);
    out += ", \"columns\": [\"theta_deg\", \"phi_deg\", \"albedo\", \"albedo_se\"";
    if (m.against()) out += ", \"reference\", \"reference_se\", \"relative_difference\"";
    out += "], \"rows\": [";
    for (std::size_t r = 0; r < m.rows.size(); ++r) {
        out += r ? ", [" : "[";
        out += json_number(m.rows[r].theta_deg) + ", " + json_number(m.rows[r].phi_deg) + ", " +
               json_array(m.rows[r].albedo) + ", " + json_array(m.rows[r].standard_error);
        if (m.against())
            out += ", " + json_array(m.reference_rows[r].albedo) + ", " + json_array(m.reference_rows[r].standard_error) +
                   ", " + json_array(c.relative[r]);
        out += "]";
    }
    out += "]";
    if (m.against()) {
        out += ", \"worst\": {\"relative_difference\": " + json_number(c.worst) +
               ", \"standard_error\": " + json_number(c.standard_error) +
               ", \"theta_deg\": " + json_number(m.rows[c.row].theta_deg) +
               ", \"phi_deg\": " + json_number(m.rows[c.row].phi_deg) + ", \"channel\": " + json_channel(m.channels, c.channel) +
               "}";
    }
    return out + "}\n";
}

// The largest relative standard error of both tables, for the estimator line.
double largest_relative_error(const Measurement& m) {
    double largest = 0.0;
    for (const std::vector<AlbedoRow>* rows : {&m.rows, &m.reference_rows}) {
        for (const AlbedoRow& row : *rows) {
            for (std::size_t k = 0; k < m.channels.size(); ++k) {
                if (row.albedo[k] > 0.0) largest = std::max(largest, row.standard_error[k] / row.albedo[k]);
            }
        }
    }
    return largest;
}

// The text's comment lines: what was measured, in which channels, by which estimator.
std::string text_comments(const Measurement& m, bool summary) {
    const Channels& channels = m.channels;
    std::string out = "# directional albedo a(wi) = integral f_r cos(theta_o) d(wo); view angles in degrees\n";
    out += "# material:  " + describe_material(m.material_path, *m.material) + "\n";
    if (m.against()) out += "# reference: " + describe_material(m.reference_path, *m.reference) + "\n";
    out += "# channels:  " + (summary ? std::to_string(channels.size()) + " wavelengths " +
                                            format("%g", channels.wavelengths().front()) + " .. " +
                                            format("%g", channels.wavelengths().back()) +
                                            " nm (Y: CIE-luminance-weighted mean, min, max over them)"
                                      : channels.describe() + (channels.is_rgb() ? "" : " nm")) + "\n";
    const int samples = m.options.estimator.samples;
    const std::string monte_carlo =
        std::to_string(samples) + " x " + std::to_string(samples) + " cells, material sampler + cosine (MIS)";
    auto estimator_of = [&](const std::vector<AlbedoRow>& rs) {
        return !rs.empty() && rs[0].by_quadrature ? std::string("quadrature on the factor tables") : monte_carlo;
    };
    const std::string material_estimator = estimator_of(m.rows);
    if (!m.against() || estimator_of(m.reference_rows) == material_estimator) {
        out += "# estimator: " + material_estimator;
    } else {
        out += "# estimator: material " + material_estimator + "; reference " + estimator_of(m.reference_rows);
    }
    return out + "; largest relative standard error " + format("%.2g", 100.0 * largest_relative_error(m)) + " %\n";
}

// The table as cells, header first: theta (phi), the material's values, and with a reference "|",
// its values, "|" and the differences. More than kMaxChannelColumns channels are summarised.
std::vector<std::vector<std::string>> table_cells(const Measurement& m, const Comparison& c, bool summary, bool with_phi) {
    const std::size_t n = m.channels.size();
    const std::vector<std::string> names = channel_names(m.channels);
    const std::vector<double> y_weights = summary ? summary_weights(m.channels.wavelengths()) : std::vector<double>();
    const std::vector<std::string> value_names = summary ? std::vector<std::string>{"Y", "min", "max"} : names;
    auto values_of = [&](const std::vector<double>& a) {
        if (!summary) return a;
        double y = 0.0;
        for (std::size_t k = 0; k < n; ++k) y += y_weights[k] * a[k];
        return std::vector<double>{y, *std::min_element(a.begin(), a.end()), *std::max_element(a.begin(), a.end())};
    };
    std::vector<std::string> header = {"theta"};
    if (with_phi) header.push_back("phi");
    for (const std::string& s : value_names) header.push_back(s);
    if (m.against()) {
        header.push_back("|");
        for (const std::string& s : value_names) header.push_back("ref " + s);
        header.push_back("|");
        if (summary) {
            for (const char* s : {"diff Y", "worst", "at"}) header.push_back(s);
        } else {
            for (const std::string& s : names) header.push_back("diff " + s);
        }
    }
    std::vector<std::vector<std::string>> table = {header};
    for (std::size_t r = 0; r < m.rows.size(); ++r) {
        std::vector<std::string> line = {format("%g", m.rows[r].theta_deg)};
        if (with_phi) line.push_back(format("%g", m.rows[r].phi_deg));
        const std::vector<double> mine = values_of(m.rows[r].albedo);
        for (double v : mine) line.push_back(format("%.5f", v));
        if (m.against()) {
            line.push_back("|");
            const std::vector<double> theirs = values_of(m.reference_rows[r].albedo);
            for (double v : theirs) line.push_back(format("%.5f", v));
            line.push_back("|");
            if (summary) {
                std::size_t k = 0;
                for (std::size_t j = 1; j < n; ++j) {
                    if (std::fabs(c.relative[r][j]) > std::fabs(c.relative[r][k])) k = j;
                }
                line.push_back(percent(relative_albedo_difference(mine[0], theirs[0])));
                line.push_back(percent(c.relative[r][k]));
                line.push_back(names[k]);
            } else {
                for (double d : c.relative[r]) line.push_back(percent(d));
            }
        }
        table.push_back(line);
    }
    return table;
}

// Every column right-aligned to its widest cell, two spaces apart.
std::string aligned(const std::vector<std::vector<std::string>>& table) {
    std::vector<std::size_t> width(table.front().size(), 0);
    for (const auto& line : table) {
        for (std::size_t k = 0; k < line.size(); ++k) width[k] = std::max(width[k], line[k].size());
    }
    std::string out;
    for (const auto& line : table) {
        std::string text;
        for (std::size_t k = 0; k < line.size(); ++k) {
            if (k) text += "  ";
            text += std::string(width[k] - line[k].size(), ' ') + line[k];
        }
        out += text + "\n";
    }
    return out;
}

// Text: a few comment lines, a header, one row per direction, and the worst difference.
std::string text_report(const Measurement& m, const Comparison& c) {
    const bool summary = m.channels.size() > kMaxChannelColumns;
    const bool with_phi = m.options.phi_deg.size() != 1 || m.options.phi_deg[0] != 0.0;
    std::string out = text_comments(m, summary) + aligned(table_cells(m, c, summary, with_phi));
    if (m.against()) {
        const AlbedoRow& worst_row = m.rows[c.row];
        out += "worst relative difference: " + percent(c.worst) + " +- " + format("%.2f%%", 100.0 * c.standard_error) +
               " (" + m.channels.name(c.channel) + ") at theta " + format("%g", worst_row.theta_deg) +
               (with_phi ? ", phi " + format("%g", worst_row.phi_deg) : std::string()) + ": material " +
               format("%.5f", c.material) + ", reference " + format("%.5f", c.reference) + "\n";
    }
    return out;
}

}  // namespace

int run_albedo(const std::vector<std::string>& args) {
    const CommandLine cl = read_command_line(kHelp, kFlags, args);
    cl.expect_positional(1, 1, "one MATERIAL");
    const Measurement m = measure(cl);
    const Comparison c = compare(m);
    const std::string out = cl.has("--json") ? json_report(m, c) : text_report(m, c);
    std::fwrite(out.data(), 1, out.size(), stdout);
    return 0;
}

}  // namespace npf::cli
