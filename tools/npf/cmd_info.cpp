// npf info FILE...: what a user wants to know about a material before converting it; with
// --check, whether each file would shade (for pipelines: docs/farms.md).
#include "command_line.h"
#include "commands.h"

#include <npf/materials/material_formats.h>
#include <npf/materials/open_material.h>
#include <npf/core/number_text.h>
#include <npf/core/error.h>
#include <npf/core/text.h>
#include <npf/core/input_file.h>
#include <npf/core/json_text.h>
#include <npf/shading/npf_closure.h>
#include <npf/shading/npf_texture_file.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = flag_table({
    "--json  print a JSON array, one object per file, instead of the text",
    "--check  only check that each FILE would shade: one line per file, 'ok: FILE' or 'error: FILE: "
    "PROBLEM'; exit 1 if any would not",
    "--formats  print the material formats npf reads, each with its documentation (Markdown; the "
    "text of docs/measured-readers.md), and no FILE",
});

const char* kHelp =
    "usage: npf info FILE... [--json] [--check]\n       npf info --formats\n\nPrints format, isotropy, channels (wavelength range "
    "and count), grid sizes, description and size of each material: RGL .bsdf, MERL .binary, NPF "
    "texture .exr, Neural BRDF .h5 or analytic recipe .yaml.\n\nWith --check, opens each file as "
    "a renderer would (factor textures as NpfClosure does, on both paths) and prints one line per "
    "file; exit status 1 when any would not shade (docs/farms.md).\n\n";

std::string human_bytes(std::uint64_t n) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    double v = double(n);
    int u = 0;
    while (v >= 1024.0 && u < 4) {
        v /= 1024.0;
        ++u;
    }
    char buf[64];
    std::snprintf(buf, sizeof(buf), u == 0 ? "%.0f %s" : "%.1f %s", v, units[u]);
    return buf;
}

std::string format_name(const std::string& f) {
    if (f == "rgl") return "RGL measured BRDF (tensor_file 1.0, .bsdf)";
    if (f == "merl") return "MERL measured BRDF (.binary)";
    if (f == "npf-exr") return "NPF factor texture (OpenEXR, .exr; docs/format.md)";
    if (f == "analytic") return "analytic material recipe (YAML, .yaml; docs/synth.md)";
    return f;
}

std::string channel_summary(const Channels& c) {
    if (c.is_rgb()) return "RGB (linear sRGB), 3 channels";
    const std::vector<float>& w = c.wavelengths();
    char buf[128];
    std::snprintf(buf, sizeof(buf), "spectral, %zu wavelengths, %.1f to %.1f nm", w.size(), double(w.front()),
                  double(w.back()));
    return buf;
}

// The text output's content as one JSON object: wavelengths as numbers, details as strings.
std::string json_object(const std::string& path, const BrdfInfo& i, std::uint64_t bytes) {
    std::string out = "{\"file\": " + json_string(path) + ", \"format\": " + json_string(i.format) +
                      ", \"format_name\": " + json_string(format_name(i.format)) +
                      ", \"description\": " + json_string(i.description) +
                      ", \"size_bytes\": " + std::to_string(bytes) +
                      ", \"isotropic\": " + (i.isotropic ? "true" : "false") +
                      ", \"channels\": " + json_string(i.channels.is_rgb() ? "rgb" : "spectral") +
                      ", \"channel_count\": " + std::to_string(i.channels.size()) + ", \"wavelengths_nm\": ";
    if (i.channels.is_rgb()) {
        out += "null";
    } else {
        out += "[";
        const std::vector<float>& w = i.channels.wavelengths();
        for (std::size_t k = 0; k < w.size(); ++k) out += (k ? ", " : "") + json_number(double(w[k]), 7);
        out += "]";
    }
    out += ", \"value_bound\": " + json_number(i.value_bound);
    out += ", \"details\": {";
    for (std::size_t k = 0; k < i.details.size(); ++k) {
        out += (k ? ", " : "") + json_string(i.details[k].first) + ": " + json_string(i.details[k].second);
    }
    return out + "}}";
}

// What keeps `path` from shading, "" when nothing does. Factor textures, and the TIFF copies image
// tools make of them, are opened as a renderer opens them: by NpfClosure on both of its paths
// (arrays, and OpenImageIO's TextureSystem with its own checks); every other source by
// open_material, as the other commands open it.
std::string shading_problem(const std::string& path) {
    try {
        if (is_npf_texture_or_copy(path)) {
            // One after the other, so that the check costs what shading costs, not twice that.
            { const NpfClosure in_memory(path, NpfClosure::Path::Memory); }
            { const NpfClosure through_textures(path, NpfClosure::Path::Texture); }
        } else {
            open_material(path);
        }
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

int run_check(const std::vector<std::string>& paths, bool json) {
    std::string json_text;
    std::size_t failed = 0;
    for (const std::string& path : paths) {
        const std::string problem = shading_problem(path);
        if (!problem.empty()) ++failed;
        if (json) {
            json_text += (json_text.empty() ? "[" : ",\n ") + std::string("{\"file\": ") + json_string(path) +
                         ", \"ok\": " + (problem.empty() ? "true" : "false") +
                         ", \"error\": " + (problem.empty() ? "null" : json_string(problem)) + "}";
        } else if (problem.empty()) {
            std::printf("ok: %s\n", path.c_str());
        } else {
            std::printf("error: %s\n", problem.c_str());
        }
    }
    if (json) std::printf("%s]\n", json_text.c_str());
    if (failed > 0) {
        throw Error("", std::to_string(failed) + " of " + std::to_string(paths.size()) +
                            (paths.size() == 1 ? " file" : " files") + " would not shade");
    }
    return 0;
}

}  // namespace

int run_info(const std::vector<std::string>& args) {
    const CommandLine cl = read_command_line(kHelp, kFlags, args);
    if (cl.has("--formats")) {
        cl.expect_positional(0, 0, "no FILE with --formats");
        std::fputs(describe_material_formats().c_str(), stdout);
        return 0;
    }
    cl.expect_positional(1, SIZE_MAX, "one or more FILEs");
    const bool json = cl.has("--json");
    if (cl.has("--check")) return run_check(cl.positional(), json);
    std::string json_text;  // printed whole at the end: an error leaves no half array
    bool first = true;
    for (const std::string& path : cl.positional()) {
        std::unique_ptr<Brdf> brdf = open_material(path);
        const BrdfInfo& i = brdf->info();
        // A recipe holds no data (file_bytes 0): its size is that of the text.
        const std::uint64_t bytes = i.format == "analytic" ? require_regular_file(path) : i.file_bytes;
        if (json) {
            json_text += (first ? "[" : ",\n ") + json_object(path, i, bytes);
            first = false;
            continue;
        }
        if (!first) std::printf("\n");
        first = false;
        // Names and descriptions come from files: escaped, so that none can split or repaint a line.
        std::printf("file: %s\n", printable(path).c_str());
        std::printf("format: %s\n", format_name(i.format).c_str());
        std::printf("description: %s\n", i.description.empty() ? "(none)" : printable(i.description).c_str());
        std::printf("size: %llu bytes (%s)\n", static_cast<unsigned long long>(bytes), human_bytes(bytes).c_str());
        std::printf("isotropic: %s\n", i.isotropic ? "yes" : "no");
        std::printf("channels: %s\n", channel_summary(i.channels).c_str());
        if (!i.channels.is_rgb()) std::printf("wavelengths (nm): %s\n", i.channels.describe().c_str());
        std::printf("value bound: %s 1/sr (the largest f_r cos(theta_i) cos(theta_o) its tables can give)\n",
                    number_text(i.value_bound).c_str());
        for (const auto& [key, value] : i.details) std::printf("%s: %s\n", printable(key).c_str(), printable(value).c_str());
    }
    if (json) std::printf("%s]\n", json_text.c_str());
    return 0;
}

}  // namespace npf::cli
