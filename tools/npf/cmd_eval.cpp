// npf eval FILE: a scriptable probe. Reads direction pairs (wi, wo) and prints one line of
// values per pair: f_r in 1/sr, or f_r cos(theta_o) with --cos.
#include "command_line.h"
#include "commands.h"

#include <npf/converter/open_material.h>
#include <npf/core/error.h>
#include <npf/core/input_file.h>
#include <npf/core/json_text.h>
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

const std::vector<FlagSpec> kFlags = {
    {"--dirs", true, "file of direction pairs, one 'wi_x wi_y wi_z wo_x wo_y wo_z' per line ('-': stdin, the default)"},
    {"--cos", false, "print f_r cos(theta_o) = f_r * wo.z (the RGL reference readers' convention)"},
    {"--wavelengths", true, "spectral files: evaluate at '450,550,650' or 'start:end:count' (nm)"},
    {"--raw", false, "keep negative values (out-of-gamut RGB) instead of clamping them to 0"},
    {"--pdf", false, "append a column 'pdf': the density (1/sr) with which the material samples wo given wi"},
    {"--path", true, "NPF textures (.exr): 'memory' (tables in arrays, the default) or 'texture' (lookups through "
                     "OpenImageIO's TextureSystem); a comment line names the path used"},
    {"--json", false, "print one JSON object (channels, then a row per pair: values and pdf) instead of the text"},
    {"--help", false, "show this help"},
};

const char* kHelp =
    "usage: npf eval FILE [--dirs PATH|-] [--cos] [--wavelengths LIST] [--raw] [--pdf] [--path memory|texture]\n"
    "                [--json]\n\n"
    "FILE is any material: RGL .bsdf, MERL .binary, NPF texture .exr, Neural BRDF .h5 or analytic recipe .yaml.\n"
    "Directions are in the local frame (z the normal, x the tangent), both pointing away from the\n"
    "surface, and are normalised on reading; lines starting with '#' and blank lines are skipped.\n"
    "Output: a header '# ' with the channel names (R G B) or wavelengths (nm), then one line per\n"
    "pair. A pair with either direction at or below the horizon gives 0.\n\n";

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

}  // namespace

int run_eval(const std::vector<std::string>& args) {
    CommandLine cl("eval", args, kFlags);
    if (cl.has("--help")) {
        std::printf("%s%s", kHelp, usage_lines(kFlags).c_str());
        return 0;
    }
    cl.expect_positional(1, 1, "one FILE");
    const std::string path = cl.positional()[0];
    std::unique_ptr<Brdf> brdf;
    std::string path_line, path_kind = "null";
    if (cl.has("--path")) {
        const std::string kind = cl.value("--path");
        if (kind != "memory" && kind != "texture") {
            throw Error("--path", "expected 'memory' or 'texture', got '" + kind + "'");
        }
        if (!is_npf_texture(path)) {
            require_regular_file(path, "a material file");
            throw Error(path, "--path applies to NPF factor textures (.exr) only");
        }
        const bool texture = kind == "texture";
        brdf = std::make_unique<NpfBrdf>(path, texture ? NpfClosure::Path::Texture : NpfClosure::Path::Memory);
        path_line = texture ? "# path texture (OpenImageIO TextureSystem)\n" : "# path memory\n";
        path_kind = json_string(kind);
    } else {
        brdf = open_material(path);
    }

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
    const std::string dirs_name = reader->name();

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
    std::string line;
    char buf[64];
    while (reader->next(line)) {
        const std::size_t line_no = reader->line_number();
        auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        double v[6];
        std::string why;
        if (!parse_pair(line, v, why)) throw Error(dirs_name + ":" + std::to_string(line_no), why);
        Vec3 wi, wo;  // parse_pair let only finite numbers through
        if (!unit_direction(v[0], v[1], v[2], wi) || !unit_direction(v[3], v[4], v[5], wo)) {
            throw Error(dirs_name + ":" + std::to_string(line_no), "a direction of zero length");
        }
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
