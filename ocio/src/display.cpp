// DisplayTransform: the config search, name resolution and one OpenColorIO CPU processor.
#include <npf/color/display.h>
#include <npf/core/error.h>
#include <npf/core/text_input.h>

#include "config_checks.h"

#include <OpenColorIO/OpenColorIO.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <utility>

// Set by ocio/CMakeLists.txt: the shipped config in the source tree, in the configured install
// prefix, and relative to the installed executables' folder.
#if !defined(NPF_OCIO_CONFIG_SOURCE) || !defined(NPF_OCIO_CONFIG_INSTALLED) || \
    !defined(NPF_OCIO_CONFIG_FROM_BINDIR)
#error "ocio/CMakeLists.txt defines the shipped OCIO config locations"
#endif

namespace OCIO = OCIO_NAMESPACE;

namespace npf::color {

namespace {

namespace fs = std::filesystem;

// Where the config came from, for error messages: a bad $OCIO is a different fix from a bad flag.
enum class ConfigOrigin { Explicit, Environment, Shipped };

std::string environment_config() {
    const char* v = std::getenv("OCIO");
    return v ? std::string(v) : std::string();
}

std::string executable_relative_config() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec || exe.empty()) return {};
    return (exe.parent_path() / NPF_OCIO_CONFIG_FROM_BINDIR).lexically_normal().string();
}

std::string join(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& s : items) out += (out.empty() ? "'" : ", '") + s + "'";
    return out.empty() ? "none" : out;
}

std::pair<std::string, ConfigOrigin> resolve_with_origin(const std::string& explicit_path) {
    if (!explicit_path.empty()) return {explicit_path, ConfigOrigin::Explicit};
    if (std::string env = environment_config(); !env.empty()) return {env, ConfigOrigin::Environment};
    const std::vector<std::string> candidates = shipped_ocio_config_candidates();
    for (const std::string& c : candidates) {
        std::error_code ec;
        if (!c.empty() && fs::is_regular_file(c, ec)) return {c, ConfigOrigin::Shipped};
    }
    throw Error("OpenColorIO config", "none given, $OCIO is not set and the shipped config is not in " +
                                          join(candidates) + "; pass a config file or set $OCIO");
}

struct LoadedConfig {
    std::string path;
    OCIO::ConstConfigRcPtr config;
};

LoadedConfig load_config(const std::string& explicit_path) {
    auto [path, origin] = resolve_with_origin(explicit_path);
    const std::string note = origin == ConfigOrigin::Environment ? " (named by $OCIO)" : "";
    std::error_code ec;
    if (!fs::exists(path, ec)) throw Error(path, "OpenColorIO config not found" + note);
    if (fs::is_directory(path, ec)) throw Error(path, "is a folder, not an OpenColorIO config" + note);
    // Read within bounds (a regular file, kConfigTextBounds, no NUL) and checked before OCIO
    // parses it (config_checks.h); OCIO gets the text.
    const std::string text = read_text_file(path, "an OpenColorIO config", kConfigTextBounds);
    detail::check_config_text(text, path);
    OCIO::ConfigRcPtr config;
    try {
        std::istringstream stream(text);
        config = OCIO::Config::CreateFromStream(stream)->createEditableCopy();
        // CreateFromFile would set this (AbsPath of the file, its folder): relative search paths
        // start there.
        const fs::path absolute = fs::absolute(path, ec);
        config->setWorkingDir((ec ? fs::path(path) : absolute).lexically_normal().parent_path().string().c_str());
    } catch (const std::exception& e) {
        throw Error(path, std::string("invalid OpenColorIO config") + note + ": " + detail::ocio_reason(e));
    }
    // Before validate(), which resolves context variables without a bound, and before any
    // processor, which follows references by recursion.
    detail::check_config_graph(*config, path);
    try {
        config->validate();
    } catch (const OCIO::Exception& e) {
        throw Error(path, std::string("invalid OpenColorIO config") + note + ": " + detail::ocio_reason(e, config.get()));
    }
    return {path, config};
}

std::vector<std::string> active_displays(const OCIO::Config& config) {
    std::vector<std::string> out;
    for (int i = 0; i < config.getNumDisplays(); ++i) out.emplace_back(config.getDisplay(i));
    return out;
}

// Every view of a display, active or not: its own views and the shared views it uses.
std::vector<std::string> all_views(const OCIO::Config& config, const std::string& display) {
    std::vector<std::string> out;
    for (OCIO::ViewType type : {OCIO::VIEW_DISPLAY_DEFINED, OCIO::VIEW_SHARED})
        for (int i = 0; i < config.getNumViews(type, display.c_str()); ++i)
            out.emplace_back(config.getView(type, display.c_str(), i));
    return out;
}

// The active views of a display (the config's view list), the default first.
std::vector<std::string> active_views(const OCIO::Config& config, const std::string& display) {
    std::vector<std::string> out{config.getDefaultView(display.c_str())};
    for (int i = 0; i < config.getNumViews(display.c_str()); ++i) {
        std::string v = config.getView(display.c_str(), i);
        if (v != out.front()) out.push_back(std::move(v));
    }
    if (out.front().empty()) out.erase(out.begin());
    return out;
}

bool contains(const std::vector<std::string>& list, const std::string& item) {
    for (const std::string& s : list)
        if (s == item) return true;
    return false;
}

// The config's colour space for `input`: the first of the known names (or aliases) it has,
// else the role. An explicit name wins over both.
std::string resolve_input(const OCIO::Config& config, const DisplayOptions& options, const std::string& path) {
    if (!options.input_colorspace.empty()) {
        OCIO::ConstColorSpaceRcPtr cs = config.getColorSpace(options.input_colorspace.c_str());
        if (!cs) throw Error(path, "unknown colour space '" + options.input_colorspace + "'");
        return cs->getName();
    }
    const bool xyz = options.input == SceneSpace::CieXyzD65;
    const std::vector<std::string> names =
        xyz ? std::vector<std::string>{"CIE XYZ-D65 - Scene-referred", "lin_ciexyz_d65"}
            : std::vector<std::string>{"Linear Rec.709 (sRGB)", "lin_rec709", "Utility - Linear - sRGB"};
    const char* role = xyz ? "cie_xyz_d65_interchange" : OCIO::ROLE_SCENE_LINEAR;
    for (const std::string& n : names)
        if (OCIO::ConstColorSpaceRcPtr cs = config.getColorSpace(n.c_str())) return cs->getName();
    if (config.hasRole(role))
        if (OCIO::ConstColorSpaceRcPtr cs = config.getColorSpace(role)) return cs->getName();
    throw Error(path, std::string("no ") + (xyz ? "CIE XYZ D65" : "linear Rec.709") +
                          " colour space: none of " + join(names) + " and no role '" + role +
                          "'; name the input colour space");
}

}  // namespace

std::vector<std::string> shipped_ocio_config_candidates() {
    std::vector<std::string> out;
    if (std::string exe = executable_relative_config(); !exe.empty()) out.push_back(std::move(exe));
    out.emplace_back(NPF_OCIO_CONFIG_SOURCE);
    out.emplace_back(NPF_OCIO_CONFIG_INSTALLED);
    return out;
}

std::string resolve_ocio_config_path(const std::string& explicit_path) {
    return resolve_with_origin(explicit_path).first;
}

std::vector<DisplayViews> list_display_views(const std::string& config_path) {
    const LoadedConfig loaded = load_config(config_path);
    try {
        const OCIO::Config& config = *loaded.config;
        std::vector<std::string> displays = active_displays(config);
        const std::string default_display = config.getDefaultDisplay();
        std::vector<DisplayViews> out;
        if (!default_display.empty()) out.push_back({default_display, active_views(config, default_display)});
        for (const std::string& d : displays)
            if (d != default_display) out.push_back({d, active_views(config, d)});
        return out;
    } catch (const OCIO::Exception& e) {
        throw Error(loaded.path, detail::ocio_reason(e, loaded.config.get()));
    }
}

struct DisplayTransform::Impl {
    std::string config_path, display, view, input;
    OCIO::ConstConfigRcPtr config;
    OCIO::ConstCPUProcessorRcPtr cpu;
};

DisplayTransform::DisplayTransform(const DisplayOptions& options) : m_impl(std::make_unique<Impl>()) {
    LoadedConfig loaded = load_config(options.config_path);
    Impl& im = *m_impl;
    im.config_path = loaded.path;
    im.config = loaded.config;
    const OCIO::Config& config = *im.config;
    try {
        im.display = options.display.empty() ? config.getDefaultDisplay() : options.display;
        if (config.getDisplayAllByName(im.display.c_str()) < 0)
            throw Error(im.config_path, "unknown display '" + im.display + "' (displays: " +
                                            join(active_displays(config)) + ")");
        im.view = options.view.empty() ? config.getDefaultView(im.display.c_str()) : options.view;
        if (im.view.empty() || !contains(all_views(config, im.display), im.view))
            throw Error(im.config_path, "unknown view '" + im.view + "' for display '" + im.display +
                                            "' (views: " + join(active_views(config, im.display)) + ")");
        im.input = resolve_input(config, options, im.config_path);
        // The LUTs this processor opens, before OCIO opens them.
        detail::check_display_luts(config, im.config_path, im.input, im.display, im.view);

        OCIO::DisplayViewTransformRcPtr dvt = OCIO::DisplayViewTransform::Create();
        dvt->setSrc(im.input.c_str());
        dvt->setDisplay(im.display.c_str());
        dvt->setView(im.view.c_str());
        // Built once; the CPU processor is immutable and shared by every apply().
        im.cpu = config.getProcessor(dvt)->getDefaultCPUProcessor();
    } catch (const OCIO::Exception& e) {
        throw Error(im.config_path, "cannot build the display transform: " + detail::ocio_reason(e, &config));
    }
}

DisplayTransform::~DisplayTransform() = default;
DisplayTransform::DisplayTransform(DisplayTransform&&) noexcept = default;
DisplayTransform& DisplayTransform::operator=(DisplayTransform&&) noexcept = default;

const std::string& DisplayTransform::config_path() const { return m_impl->config_path; }
const std::string& DisplayTransform::display() const { return m_impl->display; }
const std::string& DisplayTransform::view() const { return m_impl->view; }
const std::string& DisplayTransform::input_colorspace() const { return m_impl->input; }

void DisplayTransform::apply(float* pixels, std::size_t width, std::size_t height, int channels) const {
    if (channels != 3 && channels != 4)
        throw Error(m_impl->config_path, "a display transform takes 3 or 4 channels per pixel, not " +
                                             std::to_string(channels));
    if (width == 0 || height == 0) return;
    if (!pixels) throw Error(m_impl->config_path, "no pixels to transform");
    try {
        OCIO::PackedImageDesc image(pixels, static_cast<long>(width), static_cast<long>(height), channels);
        m_impl->cpu->apply(image);
    } catch (const OCIO::Exception& e) {
        throw Error(m_impl->config_path, "display transform failed: " + detail::ocio_reason(e));
    }
}

std::array<double, 3> DisplayTransform::apply(const std::array<double, 3>& colour) const {
    float rgb[3] = {static_cast<float>(colour[0]), static_cast<float>(colour[1]), static_cast<float>(colour[2])};
    try {
        m_impl->cpu->applyRGB(rgb);
    } catch (const OCIO::Exception& e) {
        throw Error(m_impl->config_path, "display transform failed: " + detail::ocio_reason(e));
    }
    return {rgb[0], rgb[1], rgb[2]};
}

}  // namespace npf::color
