#include "output_header.h"

#include <npf/core/text.h>
#include <npf/shading/npf_texture_file.h>
#include <npf/shading/npf_texture_layout.h>

#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>

namespace npf::batch::detail {

namespace {

// A figure's text, or null when it is not there.
using Lookup = std::function<const std::string*(const std::string& key)>;

std::optional<double> number_at(const Lookup& find, const std::string& key) {
    const std::string* text = find(key);
    if (!text) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(text->c_str(), &end);
    if (end == text->c_str()) return std::nullopt;
    return v;
}

void fill_figures(MaterialResult& r, const Lookup& find) {
    r.error_mean = number_at(find, npf_exr::kMetaErrorMean);
    r.error_max = number_at(find, npf_exr::kMetaErrorMax);
    r.fitted_error_mean = number_at(find, npf_exr::kMetaFittedErrorMean);
    r.fitted_error_max = number_at(find, npf_exr::kMetaFittedErrorMax);
    r.albedo_max = number_at(find, npf_exr::kMetaAlbedoMax);
    r.edits.clear();
    for (int k = 1; k < 1000; ++k) {
        char key[32];
        std::snprintf(key, sizeof key, "%s%03d", npf_exr::kMetaEditPrefix, k);
        const std::string* entry = find(key);
        if (!entry) break;
        r.edits.push_back(first_line(*entry));
    }
}

std::string figure_text(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.9g", v);
    return b;
}

}  // namespace

std::optional<Header> header_of(const std::string& path, bool npf_texture) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
    if (npf_texture && !is_npf_texture(path)) return std::nullopt;
    // The OpenEXR reader whatever the name says (OpenImageIO would choose by the extension).
    auto in = OIIO::ImageInput::create("openexr");
    OIIO::ImageSpec spec;
    if (!in || !in->open(path, spec)) {
        OIIO::geterror();  // clear it
        return std::nullopt;
    }
    Header out;
    for (const OIIO::ParamValue& p : in->spec().extra_attribs) {
        if (p.type() == OIIO::TypeString) out[p.name().string()] = p.get_string();
    }
    in->close();
    return out;
}

void fill_recorded_figures(MaterialResult& r, const Header& output_header) {
    const std::string prefix = npf_exr::kMetadataPrefix;
    fill_figures(r, [&](const std::string& key) -> const std::string* {
        const auto it = output_header.find(prefix + key);
        return it == output_header.end() ? nullptr : &it->second;
    });
}

void fill_recorded_figures(MaterialResult& r, const std::vector<std::pair<std::string, std::string>>& metadata) {
    fill_figures(r, [&](const std::string& key) -> const std::string* {
        // The last of equal keys, as the header keeps it.
        for (auto it = metadata.rbegin(); it != metadata.rend(); ++it)
            if (it->first == key) return &it->second;
        return nullptr;
    });
}

LightingCheck lighting_check_of(const std::string& label, const Header& h) {
    const Lookup find = [&h](const std::string& key) -> const std::string* {
        const auto it = h.find(key);
        return it == h.end() ? nullptr : &it->second;
    };
    const double inf = std::numeric_limits<double>::infinity();
    return {label, number_at(find, "npf:batch_psnr").value_or(inf), number_at(find, "npf:batch_psnr_floor").value_or(inf),
            number_at(find, "npf:batch_ssim").value_or(1.0), number_at(find, "npf:batch_relmse").value_or(0.0)};
}

std::vector<std::pair<std::string, std::string>> render_figures_metadata(const LightingCheck& c) {
    return {{"npf:batch_psnr", figure_text(c.psnr)},
            {"npf:batch_psnr_floor", figure_text(c.psnr_floor)},
            {"npf:batch_ssim", figure_text(c.ssim)},
            {"npf:batch_relmse", figure_text(c.relmse)}};
}

}  // namespace npf::batch::detail
