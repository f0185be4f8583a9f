#include <npf/materials/material_formats.h>

#include <utility>

namespace npf {

namespace {

const std::vector<MaterialFormat>& shipped() {
    // The shipped formats, one line each, in the order detection asks them: by name first
    // (recipes), then by content, the most specific signature first.
    static const std::vector<MaterialFormat> formats = {
        recipe_material_format(),
        rgl_material_format(),
        merl_material_format(),
        npf_texture_material_format(),
        nbrdf_material_format(),
    };
    return formats;
}

std::vector<MaterialFormat>& registry() {
    static std::vector<MaterialFormat> formats = shipped();
    return formats;
}

}  // namespace

const std::vector<MaterialFormat>& material_formats() { return registry(); }

const std::vector<MaterialFormat>& shipped_material_formats() { return shipped(); }

void register_material_format(MaterialFormat format) { registry().push_back(std::move(format)); }

std::string material_format_list() {
    std::vector<std::string> listed;
    for (const MaterialFormat& f : registry())
        if (!f.described_as.empty()) listed.push_back(f.described_as);
    std::string text;
    for (std::size_t i = 0; i < listed.size(); ++i)
        text += (i == 0 ? "" : i + 1 == listed.size() ? " or " : ", ") + listed[i];
    return text;
}

std::string format_documentation(const MaterialFormat& format) {
    if (format.title.empty()) return "";
    return "## " + format.title + "\n\n" + format.documentation;
}

std::string describe_material_formats() {
    std::string text;
    for (const MaterialFormat& f : registry())
        if (!f.title.empty()) text += (text.empty() ? "" : "\n") + format_documentation(f);
    return text;
}

}  // namespace npf
