// npf info FILE...: what a user wants to know about a material before converting it.
#include "command_line.h"
#include "commands.h"

#include <npf/converter/open_material.h>
#include <npf/core/input_file.h>

#include <cstdio>
#include <string>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = {
    {"--help", false, "show this help"},
};

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

}  // namespace

int run_info(const std::vector<std::string>& args) {
    CommandLine cl("info", args, kFlags);
    if (cl.has("--help") || cl.positional().empty()) {
        std::printf("usage: npf info FILE...\n\nPrints format, isotropy, channels (wavelength range and "
                    "count), grid sizes, description and size of each material: RGL .bsdf, MERL .binary, NPF "
                    "texture .exr, Neural BRDF .h5 or analytic recipe .yaml.\n\n%s",
                    usage_lines(kFlags).c_str());
        return cl.has("--help") ? 0 : 2;
    }
    bool first = true;
    for (const std::string& path : cl.positional()) {
        std::unique_ptr<Brdf> brdf = open_material(path);
        const BrdfInfo& i = brdf->info();
        // A recipe holds no data (file_bytes 0): its size is that of the text.
        const std::uint64_t bytes = i.format == "analytic" ? require_regular_file(path) : i.file_bytes;
        if (!first) std::printf("\n");
        first = false;
        std::printf("file: %s\n", path.c_str());
        std::printf("format: %s\n", format_name(i.format).c_str());
        std::printf("description: %s\n", i.description.empty() ? "(none)" : i.description.c_str());
        std::printf("size: %llu bytes (%s)\n", static_cast<unsigned long long>(bytes), human_bytes(bytes).c_str());
        std::printf("isotropic: %s\n", i.isotropic ? "yes" : "no");
        std::printf("channels: %s\n", channel_summary(i.channels).c_str());
        if (!i.channels.is_rgb()) std::printf("wavelengths (nm): %s\n", i.channels.describe().c_str());
        for (const auto& [key, value] : i.details) std::printf("%s: %s\n", key.c_str(), value.c_str());
    }
    return 0;
}

}  // namespace npf::cli
