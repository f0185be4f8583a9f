// npf eval FILE: a scriptable probe. Reads direction pairs (wi, wo) and prints one line of
// values per pair: f_r in 1/sr, or f_r cos(theta_o) with --cos. With --against REF it compares two
// materials at the pairs instead (npf/core/brdf_comparison.h) and prints the summary.
#include "command_line.h"
#include "commands.h"

#include <npf/materials/open_material.h>
#include <npf/core/brdf_comparison.h>
#include <npf/core/error.h>
#include <npf/core/input_file.h>
#include <npf/core/json_text.h>
#include <npf/core/number_text.h>
#include <npf/core/text_input.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_texture_file.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <memory>
#include <sstream>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = flag_table({
    "--dirs VALUE  file of direction pairs, one 'wi_x wi_y wi_z wo_x wo_y wo_z' per line ('-': stdin, the default)",
    "--cos  print f_r cos(theta_o) = f_r * wo.z (the RGL reference readers' convention)",
    "--wavelengths VALUE  spectral files: evaluate at '450,550,650' or 'start:end:count' (nm)",
    "--raw  keep negative values (out-of-gamut RGB) instead of clamping them to 0",
    "--pdf  append a column 'pdf': the density (1/sr) with which the material samples wo given wi",
    "--path VALUE  NPF textures (.exr): 'memory' (tables in arrays, the default) or 'texture' (lookups through "
    "OpenImageIO's TextureSystem); a comment line names the path used",
    "--json  print one JSON object (channels, then a row per pair: values and pdf) instead of the text",
    "--against VALUE  compare FILE with this reference material at the pairs (default: npf convert's 500 held-out "
    "pairs) and print the relative RMS of f_r cos(theta_o) and the largest difference",
    "--max-theta VALUE  with --against: count only pairs with both directions within this angle (degrees, default 80)",
});

const char* kHelp =
    "usage: npf eval FILE [--dirs PATH|-] [--cos] [--wavelengths LIST] [--raw] [--pdf] [--path memory|texture]\n"
    "                [--json]\n"
    "       npf eval FILE --against REF [--dirs PATH|-] [--max-theta DEG] [--wavelengths LIST] [--raw] [--json]\n\n"
    "FILE is any material: RGL .bsdf, MERL .binary, NPF texture .exr, Neural BRDF .h5 or analytic recipe .yaml.\n"
    "Directions are in the local frame (z the normal, x the tangent), both pointing away from the\n"
    "surface, and are normalised on reading; lines starting with '#' and blank lines are skipped.\n"
    "Output: a header '# ' with the channel names (R G B) or wavelengths (nm), then one line per\n"
    "pair. A pair with either direction at or below the horizon gives 0.\n"
    "--against: sqrt(sum (f - f_ref)^2 / sum f_ref^2) of f_r cos(theta_o) over the pairs with both\n"
    "directions within --max-theta, every channel pooled, then per channel, within 60 degrees, and the\n"
    "largest |f - f_ref| with its pair (docs/metrics.md, \"BRDF space\").\n\n";

// Parses "x y z x y z"; returns false with a reason when the line is not six finite numbers.
bool parse_pair(const std::string& line, double v[6], std::string& why) {
    std::istringstream is(line);
    for (int k = 0; k < 6; ++k) {
        if (!(is >> v[k])) {
            why = "expected six numbers 'wi_x wi_y wi_z wo_x wo_y wo_z'";
            return false;
        }
        if (!std::isfinite(v[k])) {
            why = "non-finite number";
            return false;
        }
    }
    std::string extra;
    if (is >> extra) {
        why = "unexpected text after six numbers: '" + extra + "'";
        return false;
    }
    return true;
}

// The next pair of the file, normalised; false at its end. Comment and blank lines are skipped.
bool next_pair(LineReader& reader, Vec3& wi, Vec3& wo) {
    std::string line;
    while (reader.next(line)) {
        const std::string where = reader.name() + ":" + std::to_string(reader.line_number());
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        double v[6];
        std::string why;
        if (!parse_pair(line, v, why)) throw Error(where, why);
        // parse_pair let only finite numbers through
        if (!unit_direction(v[0], v[1], v[2], wi) || !unit_direction(v[3], v[4], v[5], wo)) {
            throw Error(where, "a direction of zero length");
        }
        return true;
    }
    return false;
}

std::string degrees_text(const Vec3& w) {
    char buf[64];
    const double theta = std::acos(std::min(1.0, std::max(-1.0, double(w.z)))) * 180.0 / kPiD;
    const double phi = std::atan2(double(w.y), double(w.x)) * 180.0 / kPiD;
    std::snprintf(buf, sizeof buf, "theta %.1f phi %.1f", theta, phi);
    return buf;
}

// npf eval FILE --against REF: the comparison's summary, as text or one JSON object.
int run_comparison(const CommandLine& cl, const std::string& path, const Brdf& test) {
    const std::string ref_path = cl.value("--against");
    if (ref_path.empty()) throw Error("--against", "needs a material file");
    const std::unique_ptr<Brdf> reference = open_material(ref_path);
    Channels channels = reference->info().channels;
    if (cl.has("--wavelengths")) {
        if (channels.is_rgb()) throw Error(ref_path, "holds RGB data; --wavelengths needs spectral materials");
        channels = Channels::spectral(parse_wavelength_list(cl.value("--wavelengths"), "--wavelengths"));
    }
    if (test.info().channels.is_rgb() != channels.is_rgb()) {
        throw Error(path, std::string("holds ") + (channels.is_rgb() ? "spectral" : "RGB") + " data and " + ref_path +
                              " does not: compare materials of one kind");
    }
    const double max_theta = cl.has("--max-theta") ? parse_finite_number(cl.value("--max-theta"), "--max-theta") : 80.0;
    if (!(max_theta > 0.0 && max_theta <= 90.0)) throw Error("--max-theta", "must lie in (0, 90] degrees");

    const bool keep_negative = cl.has("--raw");
    BrdfComparisonResult c;
    std::string pairs_text;
    if (cl.has("--dirs")) {
        const std::string dirs = cl.value("--dirs");
        std::unique_ptr<LineReader> reader = dirs == "-" ? std::make_unique<LineReader>(0, "<stdin>", kStreamTextBounds)
                                                         : std::make_unique<LineReader>(dirs, "a direction file", kStreamTextBounds);
        c = compare_brdfs(test, *reference, channels, [&](DirectionPair& p) { return next_pair(*reader, p.wi, p.wo); },
                          max_theta, keep_negative);
        pairs_text = reader->name();
    } else {
        c = compare_brdfs(test, *reference, channels, held_out_pairs(), max_theta, keep_negative);
        pairs_text = "held out (100 mirror, 100 near mirror, 300 cosine-weighted)";
    }
    if (c.used == 0) {
        char degrees[32];
        std::snprintf(degrees, sizeof degrees, "%g", max_theta);
        throw Error(cl.has("--dirs") ? cl.value("--dirs") : "--against",
                    "no pair has both directions within " + std::string(degrees) + " degrees: nothing to compare");
    }
    const BrdfComparisonResult::Worst& w = c.worst;
    if (cl.has("--json")) {
        std::string out = "{\"material\": " + json_string(path) + ", \"against\": " + json_string(ref_path) +
                          ", \"quantity\": \"f_r cos\", \"pairs\": " + std::to_string(c.pairs) + ", \"used\": " +
                          std::to_string(c.used) + ", \"max_theta\": " + json_number(max_theta) +
                          ",\n \"relative_rms\": " + json_number(c.relative_rms) + ", \"relative_rms_60\": " +
                          json_number(c.relative_rms_60) + ",\n \"channels\": [";
        for (std::size_t k = 0; k < channels.size(); ++k) {
            out += (k ? ", " : "") + std::string("{\"channel\": ") +
                   (channels.is_rgb() ? json_string(channels.name(k)) : json_number(double(channels.wavelengths()[k]), 7)) +
                   ", \"relative_rms\": " + json_number(c.channel_relative_rms[k]) + "}";
        }
        out += "],\n \"largest_difference\": {\"pair\": " + std::to_string(w.pair + 1) + ", \"channel\": " +
               json_string(channels.name(w.channel)) + ", \"value\": " + json_number(w.test) + ", \"reference\": " +
               json_number(w.reference) + ", \"wi\": [" + json_number(w.wi.x) + ", " + json_number(w.wi.y) + ", " +
               json_number(w.wi.z) + "], \"wo\": [" + json_number(w.wo.x) + ", " + json_number(w.wo.y) + ", " +
               json_number(w.wo.z) + "]}}\n";
        std::fwrite(out.data(), 1, out.size(), stdout);
        return 0;
    }
    std::printf("%s against %s, f_r cos(theta_o)%s\n", path.c_str(), ref_path.c_str(),
                cl.has("--raw") ? " (negative values kept)" : "");
    std::printf("  pairs             %zu (%s), %zu with both directions within %g deg\n", c.pairs, pairs_text.c_str(),
                c.used, max_theta);
    std::printf("  relative RMS      %.4f", c.relative_rms);
    if (channels.size() <= 8) {
        std::printf(" (");
        for (std::size_t k = 0; k < channels.size(); ++k) {
            std::printf("%s%s %.4f", k ? ", " : "", channels.name(k).c_str(), c.channel_relative_rms[k]);
        }
        std::printf(")");
    }
    std::printf("\n  within 60 deg     %.4f\n", c.relative_rms_60);
    std::printf("  largest diff.     %.6g against %.6g (%s) at pair %zu: wi %s, wo %s\n", w.test, w.reference,
                channels.name(w.channel).c_str(), w.pair + 1, degrees_text(w.wi).c_str(), degrees_text(w.wo).c_str());
    return 0;
}

// The material, and with --path the factor texture's lookup path as the text and JSON name it.
struct EvalMaterial {
    std::unique_ptr<Brdf> brdf;
    std::string path_line, path_kind = "null";
};

EvalMaterial open_for_eval(const CommandLine& cl, const std::string& path) {
    EvalMaterial m;
    if (!cl.has("--path")) {
        m.brdf = open_material(path);
        return m;
    }
    const std::string kind = cl.value("--path");
    if (kind != "memory" && kind != "texture") throw Error("--path", "expected 'memory' or 'texture', got '" + kind + "'");
    if (!is_npf_texture(path)) {
        require_regular_file(path, "a material file");
        throw Error(path, "--path applies to NPF factor textures (.exr) only");
    }
    const bool texture = kind == "texture";
    m.brdf = std::make_unique<NpfBrdf>(path, texture ? NpfClosure::Path::Texture : NpfClosure::Path::Memory);
    m.path_line = texture ? "# path texture (OpenImageIO TextureSystem)\n" : "# path memory\n";
    m.path_kind = json_string(kind);
    return m;
}

}  // namespace

int run_eval(const std::vector<std::string>& args) {
    const CommandLine cl = read_command_line(kHelp, kFlags, args);
    cl.expect_positional(1, 1, "one FILE");
    const std::string path = cl.positional()[0];
    const EvalMaterial material = open_for_eval(cl, path);
    const std::unique_ptr<Brdf>& brdf = material.brdf;
    const std::string &path_line = material.path_line, &path_kind = material.path_kind;

    if (cl.has("--against")) {
        for (const char* flag : {"--cos", "--pdf"}) {
            if (cl.has(flag)) throw Error(flag, "applies without --against only (the comparison is of f_r cos(theta_o))");
        }
        return run_comparison(cl, path, *brdf);
    }
    if (cl.has("--max-theta")) throw Error("--max-theta", "applies with --against only");

    Channels channels = brdf->info().channels;
    if (cl.has("--wavelengths")) {
        if (channels.is_rgb()) throw Error(path, "holds RGB data; --wavelengths needs a spectral file");
        channels = Channels::spectral(parse_wavelength_list(cl.value("--wavelengths"), "--wavelengths"));
    }
    ChannelQuery query = brdf->query(channels);
    query.clamp_negative = !cl.has("--raw");
    const bool with_cos = cl.has("--cos");
    const bool with_pdf = cl.has("--pdf");

    // Pairs stream through: bounded per line and in all (text_input.h), so /dev/zero or an
    // endless line is refused at once instead of filling memory.
    const std::string dirs = cl.value("--dirs", "-");
    std::unique_ptr<LineReader> reader = dirs == "-" ? std::make_unique<LineReader>(0, "<stdin>", kStreamTextBounds)
                                                     : std::make_unique<LineReader>(dirs, "a direction file", kStreamTextBounds);

    // --json: the same content as the text, the header as keys and a row object per pair.
    const bool json = cl.has("--json");
    std::string out;
    if (json) {
        out = "{\"material\": " + json_string(path) + ", \"path\": " + path_kind + ", \"quantity\": " +
              json_string(with_cos ? "f_r cos" : "f_r") + ", \"channels\": [";
        for (std::size_t k = 0; k < channels.size(); ++k) {
            out += k ? ", " : "";
            out += channels.is_rgb() ? json_string(channels.name(k)) : json_number(double(channels.wavelengths()[k]), 7);
        }
        out += "],\n \"rows\": [";
    } else {
        out = path_line + "# " + channels.describe() + (with_pdf ? " pdf" : "") + "\n";
    }
    bool first_row = true;
    std::vector<float> values(query.size());
    char buf[64];
    Vec3 wi, wo;
    while (next_pair(*reader, wi, wo)) {
        brdf->eval_cos(wi, wo, query, values.data());
        if (json) out += first_row ? "\n  {\"values\": [" : ",\n  {\"values\": [";
        first_row = false;
        for (std::size_t k = 0; k < values.size(); ++k) {
            // f_r = (f_r cos) / cos; below the horizon the value is 0 and stays 0.
            double value = values[k];
            if (!with_cos) value = wo.z > 0.f ? value / double(wo.z) : 0.0;
            if (json) {
                out += (k ? ", " : "") + json_number(value);
            } else {
                std::snprintf(buf, sizeof(buf), k ? " %.9g" : "%.9g", value);
                out += buf;
            }
        }
        if (json) {
            out += "]";
            if (with_pdf) out += ", \"pdf\": " + json_number(double(brdf->pdf(wi, wo)));
            out += "}";
        } else {
            if (with_pdf) {
                std::snprintf(buf, sizeof(buf), " %.9g", double(brdf->pdf(wi, wo)));
                out += buf;
            }
            out += '\n';
        }
        if (out.size() > (1u << 16)) {
            std::fwrite(out.data(), 1, out.size(), stdout);
            out.clear();
        }
    }
    if (json) out += "]}\n";
    std::fwrite(out.data(), 1, out.size(), stdout);
    return 0;
}

}  // namespace npf::cli
