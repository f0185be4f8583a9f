// The material formats npf opens, as a registry (the way Mitsuba registers plugins): each format
// is one file (materials/src/*_format.cpp) holding its detection, loader and user documentation
// (a MaterialFormat), and one line in the list of material_formats.cpp. open_material, its
// "unknown material format" message and the formats' documentation (describe_material_formats)
// come from the registry; a program (or a test) may add a format of its own at run time.
#pragma once

#include <npf/core/brdf.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace npf {

// What detection sees of a material file: its path, its first bytes and its size.
struct MaterialFileHead {
    std::string path;
    const std::uint8_t* bytes = nullptr;
    std::size_t count = 0;    // bytes read (at most kMaterialHeadBytes)
    std::uint64_t size = 0;   // the file's size
};
inline constexpr std::size_t kMaterialHeadBytes = 16;

struct MaterialFormat {
    // For the "unknown material format (not ...)" list, with its article: "a MERL .binary".
    // Empty: not listed (a format claimed by its name alone, as recipes are).
    std::string described_as;
    // Claims a path by its name alone, before any file is opened (analytic recipes: .yaml).
    std::function<bool(const std::string& path)> claims_name;
    // Claims a file by its first bytes and size (and its name, for a format that takes a file
    // named like it and lets its loader say what is wrong).
    std::function<bool(const MaterialFileHead& head)> claims_file;
    // Opens it; throws npf::Error naming the file for a malformed one.
    std::function<std::unique_ptr<Brdf>(const std::string& path)> open;
    // Its user documentation, in Markdown: a title ("RGL `.bsdf` (`npf::RglBrdf`, ...)") and
    // the text under it: what files it reads, what it checks, its limits, the options it takes.
    // docs/measured-readers.md holds every shipped format's, word for word (test
    // MaterialFormatDocs.*).
    std::string title;
    std::string documentation;
};

// The formats in the order they are asked: the shipped ones (material_formats.cpp), then those
// registered at run time.
const std::vector<MaterialFormat>& material_formats();
// The shipped formats alone, in the same order.
const std::vector<MaterialFormat>& shipped_material_formats();

// Adds a format, asked after the shipped ones. Not thread-safe with concurrent open_material:
// register before opening materials.
void register_material_format(MaterialFormat format);

// "an RGL tensor_file, a MERL .binary, an NPF texture .exr or a Neural BRDF .h5": the listed
// formats, for messages.
std::string material_format_list();

// The documented formats' documentation, in the order they are asked, as Markdown: for each,
// "## " + title, a blank line, its documentation (format_documentation), then a blank line.
std::string describe_material_formats();
// One format's section of that text (empty for a format without a title).
std::string format_documentation(const MaterialFormat& format);

// The shipped formats, each defined in its reader's file.
MaterialFormat recipe_material_format();
MaterialFormat rgl_material_format();
MaterialFormat merl_material_format();
MaterialFormat npf_texture_material_format();
MaterialFormat nbrdf_material_format();

}  // namespace npf
