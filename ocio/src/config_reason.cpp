// OCIO's reasons as one line, and the cause it leaves out (config_checks.h).
#include "config_checks.h"

#include <npf/color/display.h>

#include <vector>

namespace OCIO = OCIO_NAMESPACE;

namespace npf::color::detail {

namespace {

// Reasons from OCIO are cut here (a LUT error lists every reader's complaint).
constexpr std::size_t kMaxReasonBytes = 600;

// The first FileTransform of any colour space, look, view transform or named transform (for a
// reason OCIO leaves out). Only after check_config_graph: groups are then bounded.
std::string first_file(const OCIO::ConstTransformRcPtr& t) {
    if (!t) return {};
    if (auto file = OCIO::DynamicPtrCast<const OCIO::FileTransform>(t)) return file->getSrc();
    if (auto group = OCIO::DynamicPtrCast<const OCIO::GroupTransform>(t))
        for (int i = 0; i < group->getNumTransforms(); ++i)
            if (std::string f = first_file(group->getTransform(i)); !f.empty()) return f;
    return {};
}

std::string first_file(const OCIO::Config& config) {
    std::vector<OCIO::ConstTransformRcPtr> all;
    for (int i = 0; i < config.getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL); ++i)
        if (auto cs = config.getColorSpace(config.getColorSpaceNameByIndex(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL, i)))
            all.insert(all.end(), {cs->getTransform(OCIO::COLORSPACE_DIR_TO_REFERENCE), cs->getTransform(OCIO::COLORSPACE_DIR_FROM_REFERENCE)});
    for (int i = 0; i < config.getNumLooks(); ++i)
        if (auto look = config.getLook(config.getLookNameByIndex(i)))
            all.insert(all.end(), {look->getTransform(), look->getInverseTransform()});
    for (int i = 0; i < config.getNumViewTransforms(); ++i)
        if (auto vt = config.getViewTransform(config.getViewTransformNameByIndex(i)))
            all.insert(all.end(), {vt->getTransform(OCIO::VIEWTRANSFORM_DIR_TO_REFERENCE), vt->getTransform(OCIO::VIEWTRANSFORM_DIR_FROM_REFERENCE)});
    for (int i = 0; i < config.getNumNamedTransforms(OCIO::NAMEDTRANSFORM_ALL); ++i)
        if (auto nt = config.getNamedTransform(config.getNamedTransformNameByIndex(OCIO::NAMEDTRANSFORM_ALL, i)))
            all.insert(all.end(), {nt->getTransform(OCIO::TRANSFORM_DIR_FORWARD), nt->getTransform(OCIO::TRANSFORM_DIR_INVERSE)});
    for (const auto& t : all)
        if (std::string f = first_file(t); !f.empty()) return f;
    return {};
}

}  // namespace

std::string ocio_reason(const std::exception& e, const OCIO::Config* config) {
    // One line: OCIO's lines joined (a LUT error puts each reader's complaint on a line of its own).
    std::string text;
    for (const char c : std::string(e.what())) {
        const bool space = c == ' ' || c == '\t' || c == '\n' || c == '\r';
        if (!space) text += c;
        else if (!text.empty() && text.back() != ' ') text += ' ';
    }
    while (!text.empty() && text.back() == ' ') text.pop_back();
    if (text.size() > kMaxReasonBytes) {
        std::size_t cut = kMaxReasonBytes;
        while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;  // UTF-8
        text = text.substr(0, cut) + " ...";
    }
    if (text.empty()) return "OpenColorIO gave no reason";
    // Config::validate says only this when the config names LUTs and has no search path at all.
    if (text == "Config failed sanitycheck.") {
        std::string cause = "OpenColorIO gave no reason";
        if (config && config->getNumSearchPaths() == 0) {
            const std::string file = first_file(*config);
            if (!file.empty()) cause = "it names the LUT " + quote(file) + " but has no search_path to find it in";
        }
        text += " (" + cause + ")";
    }
    return text;
}

}  // namespace npf::color::detail
