// Scene-referred colour to a display, through OpenColorIO (2.1 or later).
//
// The config is chosen in this order: an explicit path, then the file named by $OCIO, then the
// config npf ships (configs/ocio/config.ocio; installed as share/npf/ocio/config.ocio). The
// display and view default to the config's; the input is npf's scene-linear Rec.709 RGB or
// the spectral renderer's CIE XYZ (D65 white, Y = 1), looked up in the config by name with a
// role as fallback. Conventions and the shipped config: docs/color.md.
//
// OpenColorIO's own types stay out of this header (npf_color links it privately).
#pragma once

#include <npf/color/spectrum.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace npf::color {

// What the scene-referred values handed to a DisplayTransform are.
enum class SceneSpace {
    // Linear Rec.709 / sRGB primaries, D65 white: npf's RGB. Looked up as "Linear Rec.709
    // (sRGB)", "lin_rec709", "Utility - Linear - sRGB", then the role scene_linear.
    LinearRec709,
    // CIE 1931 XYZ with the D65 white at Y = 1, scene-referred (npf::color::spectrum_to_xyz and
    // the hero-wavelength estimator produce it). Looked up as "CIE XYZ-D65 - Scene-referred",
    // "lin_ciexyz_d65", then the role cie_xyz_d65_interchange.
    CieXyzD65,
};

// What npf checks before OpenColorIO acts on a config (docs/color.md, "Hostile configs"): OCIO
// 2.1 recurses through references without a guard, loads a config in time that grows with the
// square of its names and sizes some LUT tables by what a file claims, so a config beyond these
// is refused with an npf::Error naming it. No config of a real pipeline comes near them.
//
// Colour spaces, display colour spaces, named transforms and all their aliases together (OCIO
// checks each new name against all earlier ones: 4096 names load in about a second).
inline constexpr std::size_t kMaxConfigNames = 4096;
// Entries of any one YAML list or map, and YAML nodes in all with anchors expanded (OCIO reads
// an alias as a copy: a few anchors nested would otherwise cost 2^n).
inline constexpr std::size_t kMaxConfigListEntries = 4096;
inline constexpr std::size_t kMaxConfigYamlNodes = std::size_t(1) << 20;
// References followed from one transform (colour space -> colour space, look, view, named
// transform, view transform) plus GroupTransform nesting: OCIO follows each by recursion.
inline constexpr int kMaxReferenceDepth = 64;
// Transforms one colour space, look, view or named transform expands to with every reference
// followed (OCIO copies a referenced space's transforms at each use: a DAG that refers twice to
// the next level doubles per level).
inline constexpr std::uint64_t kMaxExpandedTransforms = 4096;
// A LUT file (FileTransform), and the LUT files one display transform reads, counted at each
// use (OCIO builds a table for each): the largest LUT OCIO 2.1 builds (a 129^3 3D LUT, or a 1D
// LUT of 2^20 entries) is under 80 MB as text; 256 MiB leaves room for markup and comments and
// bounds what the files cost OCIO, which reads each whole.
inline constexpr std::uint64_t kMaxLutBytes = std::uint64_t(256) << 20;

struct DisplayOptions {
    std::string config_path;       // empty: $OCIO if set and non-empty, else the shipped config
    std::string display;           // empty: the config's default display
    std::string view;              // empty: the display's default view
    SceneSpace input = SceneSpace::LinearRec709;
    std::string input_colorspace;  // non-empty: this colour space (name, alias or role) instead
};

// The config a DisplayTransform with this `explicit_path` would load: the path itself when
// non-empty, else $OCIO when set and non-empty, else the first shipped config that exists.
// Throws npf::Error when none exists (listing the places looked at); does not check the file.
std::string resolve_ocio_config_path(const std::string& explicit_path = "");

// Where the shipped config is looked for, in order: beside the running executable
// (<bin>/../share/npf/ocio/config.ocio, an installed or relocated npf), the source tree this
// library was built from (a build tree), the install prefix it was configured with.
std::vector<std::string> shipped_ocio_config_candidates();

struct DisplayViews {
    std::string display;
    std::vector<std::string> views;  // the display's default view first
};

// The displays of a config (resolved as above) and their views; the default display first.
// Throws npf::Error naming the config file when it cannot be loaded or is refused (above).
std::vector<DisplayViews> list_display_views(const std::string& config_path = "");

// One display transform, built once: scene-referred input -> display-encoded output (for the
// sRGB display, sRGB-encoded values in [0, 1] for colours inside the display's range; values
// are not clipped). Immutable after construction; `apply` may be called from several threads
// at once (OpenColorIO's CPU processors are thread-safe). A moved-from transform may only be
// assigned to or destroyed.
class DisplayTransform {
public:
    // Loads and validates the config and builds the processor. Throws npf::Error naming the
    // config file for a missing, invalid or refused config (above: cycles, sizes), an unknown
    // display, view or colour space, or a LUT the processor needs that is missing, not a regular
    // file, above kMaxLutBytes, outside the config's search path or claiming more data than it
    // holds.
    explicit DisplayTransform(const DisplayOptions& options = {});
    ~DisplayTransform();
    DisplayTransform(DisplayTransform&&) noexcept;
    DisplayTransform& operator=(DisplayTransform&&) noexcept;
    DisplayTransform(const DisplayTransform&) = delete;
    DisplayTransform& operator=(const DisplayTransform&) = delete;

    const std::string& config_path() const;
    const std::string& display() const;
    const std::string& view() const;
    const std::string& input_colorspace() const;  // the config's name for the input space

    // In place on `width` x `height` packed pixels of `channels` floats each: 3 (RGB or XYZ) or
    // 4 (the fourth, alpha, passes through unchanged); OpenColorIO takes nothing else, so other
    // counts throw npf::Error. Empty images are fine.
    void apply(float* pixels, std::size_t width, std::size_t height, int channels) const;
    // One colour (linear Rec.709 RGB or XYZ, as the input space says), computed in float.
    std::array<double, 3> apply(const std::array<double, 3>& colour) const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace npf::color
