// Hostile OpenColorIO configs (docs/color.md, "Hostile configs"): each is refused with one line
// naming the config file and the cause, never a crash or a hang. Before these checks OCIO 2.1
// overflowed its stack on a reference cycle (SIGSEGV), hung on a FIFO or /dev/zero (as the
// config or as a LUT), read LUTs from anywhere, gave "Config failed sanitycheck." with no
// reason, and sized tables by what a LUT file claimed. Good configs (LUTs in their search
// path included) give the same results as before.
#include <npf/color/display.h>
#include <npf/core/error.h>

#include "error_of.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace npf::color;
using npf::testing::error_of;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

void write_file(const std::string& path, const std::string& bytes) {
    fs::create_directories(fs::path(path).parent_path());
    std::ofstream(path, std::ios::binary) << bytes;
}

// A config with a scene-referred space 'scene' (roles default and scene_linear), display 'd' with
// view 'v' showing 'scene', and the given extra colour spaces, views and top-level sections; no
// search_path line for an empty `search_path`.
std::string config_text(const std::string& spaces, const std::string& top = "", const std::string& views = "",
                        const std::string& search_path = "luts") {
    return "ocio_profile_version: 2.1\n" + (search_path.empty() ? std::string() : "search_path: \"" + search_path + "\"\n") +
           "roles: {default: scene, scene_linear: scene}\n"
           "file_rules:\n"
           "  - !<Rule> {name: Default, colorspace: default}\n"
           "displays:\n"
           "  d:\n"
           "    - !<View> {name: v, colorspace: scene}\n" +
           views + top +
           "colorspaces:\n"
           "  - !<ColorSpace> {name: scene}\n" +
           spaces;
}

std::string write_config(const std::string& dir, const std::string& text) {
    const std::string path = (fs::path(dir) / "config.ocio").string();
    write_file(path, text);
    return path;
}

// The display transform from colour space `input` of the config at `path` to view d/v.
DisplayTransform from_space(const std::string& path, const std::string& input) {
    DisplayOptions o;
    o.config_path = path;
    o.input_colorspace = input;
    return DisplayTransform(o);
}

std::string refusal(const std::string& path, const std::string& input) {
    return error_of([&] { from_space(path, input); });
}

// One line, naming the config file.
void expect_one_line_naming(const std::string& message, const std::string& path) {
    EXPECT_TRUE(has(message, path)) << message;
    EXPECT_FALSE(has(message, "\n")) << message;
}

// Writes `text` as a config in a fresh folder named after `tag`, and returns the message with
// which reading colour space A from it is refused (one line, naming the file).
std::string refused_config(const std::string& tag, const std::string& text) {
    const std::string path = write_config(npf::testing::temporary_folder(tag), text);
    const std::string m = refusal(path, "A");
    expect_one_line_naming(m, path);
    return m;
}

// ---------------------------------------------------------------------------------------------
// Reference cycles and depth: OCIO 2.1 follows references by recursion (SIGSEGV before)

TEST(ColorHostile, ColourSpaceReferringToItselfIsRefused) {
    const std::string path = write_config(npf::testing::temporary_folder("hostile_self"), config_text(
        "  - !<ColorSpace> {name: A, to_scene_reference: !<ColorSpaceTransform> {src: A, dst: scene}}\n"));
    const std::string m = refusal(path, "A");
    expect_one_line_naming(m, path);
    EXPECT_TRUE(has(m, "colour space 'A' refers to itself: refused")) << m;
    // Found when the config is loaded, whatever is asked of it.
    EXPECT_TRUE(has(error_of([&] { list_display_views(path); }), "refers to itself")) << m;
}

TEST(ColorHostile, TwoColourSpacesReferringToEachOtherAreRefused) {
    const std::string m = refused_config("hostile_pair", config_text(
        "  - !<ColorSpace> {name: A, to_scene_reference: !<ColorSpaceTransform> {src: B, dst: scene}}\n"
        "  - !<ColorSpace> {name: B, to_scene_reference: !<ColorSpaceTransform> {src: A, dst: scene}}\n"));
    EXPECT_TRUE(has(m, "colour space 'A' refers to itself through colour space 'B' -> colour space 'A': refused")) << m;
}

TEST(ColorHostile, CycleThroughNestedGroupsIsRefused) {
    const std::string m = refused_config("hostile_groups", config_text(
        "  - !<ColorSpace>\n"
        "    name: A\n"
        "    to_scene_reference: !<GroupTransform>\n"
        "      children:\n"
        "        - !<MatrixTransform> {}\n"
        "        - !<GroupTransform> {children: [!<ColorSpaceTransform> {src: B, dst: scene}]}\n"
        "  - !<ColorSpace>\n"
        "    name: B\n"
        "    from_scene_reference: !<GroupTransform> {children: [!<ColorSpaceTransform> {src: scene, dst: A}]}\n"));
    EXPECT_TRUE(has(m, "colour space 'A' refers to itself through colour space 'B' -> colour space 'A'")) << m;
}

TEST(ColorHostile, CycleThroughALookIsRefused) {
    const std::string m = refused_config("hostile_look", config_text(
        "  - !<ColorSpace> {name: A, to_scene_reference: !<LookTransform> {src: scene, dst: scene, looks: +L}}\n",
        "looks:\n"
        "  - !<Look> {name: L, process_space: A, transform: !<MatrixTransform> {}}\n"));
    EXPECT_TRUE(has(m, "colour space 'A' refers to itself through look 'L' -> colour space 'A'")) << m;
}

// A view showing named transform N, whose transform displays through that view. (OCIO 2.1's
// validate() refuses a ColorSpaceTransform naming a named transform, but not this.)
TEST(ColorHostile, CycleThroughANamedTransformIsRefused) {
    const std::string dir = npf::testing::temporary_folder("hostile_named");
    const std::string path = write_config(dir, config_text("",
        "named_transforms:\n"
        "  - !<NamedTransform> {name: N, transform: !<DisplayViewTransform> {src: scene, display: d, view: vn}}\n",
        "    - !<View> {name: vn, colorspace: N}\n"));
    const std::string m = error_of([&] {
        DisplayOptions o;
        o.config_path = path;
        o.display = "d";
        o.view = "vn";
        DisplayTransform t(o);
    });
    expect_one_line_naming(m, path);
    EXPECT_TRUE(has(m, "named transform 'N' refers to itself through view 'vn' of display 'd' -> named transform 'N'")) << m;
}

// Colour space A goes through a DisplayViewTransform to view 'tone' of display 'd', whose view
// transform 'vt' leads back to A; `view` is the line that defines view 'tone'.
std::string view_cycle_config(const std::string& view) {
    return config_text(
        "  - !<ColorSpace> {name: A, to_scene_reference: !<DisplayViewTransform> {src: scene, display: d, view: tone}}\n",
        "view_transforms:\n"
        "  - !<ViewTransform> {name: vt, from_scene_reference: !<ColorSpaceTransform> {src: A, dst: scene}}\n"
        "display_colorspaces:\n"
        "  - !<ColorSpace> {name: screen}\n",
        view);
}

// A -> DisplayViewTransform -> view 'tone' -> view transform 'vt' -> A.
TEST(ColorHostile, CycleThroughADisplayViewAndViewTransformIsRefused) {
    const std::string m = refused_config("hostile_view", view_cycle_config("    - !<View> {name: tone, view_transform: vt, display_colorspace: screen}\n"));
    EXPECT_TRUE(has(m, "colour space 'A' refers to itself through view 'tone' of display 'd'")) << m;
    EXPECT_TRUE(has(m, "view transform 'vt'")) << m;
}

// Found by npf_fuzz_ocio_config: a view showing a display space without a view transform goes
// through the default view transform (scene to display reference), which here refers back.
TEST(ColorHostile, CycleThroughTheDefaultViewTransformIsRefused) {
    const std::string m = refused_config("hostile_default_vt", view_cycle_config("    - !<View> {name: tone, colorspace: screen}\n"));
    EXPECT_TRUE(has(m, "colour space 'A' refers to itself through view 'tone' of display 'd' -> view transform 'vt' -> colour space 'A'"))
        << m;
}

TEST(ColorHostile, ReferenceChainsDeeperThanTheCapAreRefused) {
    const std::string dir = npf::testing::temporary_folder("hostile_deep");
    std::string spaces;
    for (int i = 0; i < kMaxReferenceDepth + 10; ++i)
        spaces += "  - !<ColorSpace> {name: c" + std::to_string(i) + ", to_scene_reference: !<ColorSpaceTransform> {src: c" +
                  std::to_string(i + 1) + ", dst: scene}}\n";
    spaces += "  - !<ColorSpace> {name: c" + std::to_string(kMaxReferenceDepth + 10) + "}\n";
    const std::string path = write_config(dir, config_text(spaces));
    std::string m = refusal(path, "c0");
    expect_one_line_naming(m, path);
    EXPECT_TRUE(has(m, "nest deeper than 64 levels")) << m;

    // Groups count as levels too.
    std::string group = "!<MatrixTransform> {}";
    for (int i = 0; i < kMaxReferenceDepth + 5; ++i) group = "!<GroupTransform> {children: [" + group + "]}";
    const std::string nested = write_config(npf::testing::temporary_folder("hostile_deep_groups"),
                                            config_text("  - !<ColorSpace> {name: A, to_scene_reference: " + group + "}\n"));
    m = refusal(nested, "A");
    expect_one_line_naming(m, nested);
    EXPECT_TRUE(has(m, "nest deeper than 64 levels")) << m;
}

// Each space refers twice to the next: OCIO copies the next one's transforms at each use, 2^n.
TEST(ColorHostile, ReferencesThatDoubleAtEachLevelAreRefused) {
    const std::string dir = npf::testing::temporary_folder("hostile_doubling");
    std::string spaces;
    const int levels = 20;
    for (int i = 0; i < levels; ++i) {
        const std::string next = "!<ColorSpaceTransform> {src: c" + std::to_string(i + 1) + ", dst: scene}";
        spaces += "  - !<ColorSpace> {name: c" + std::to_string(i) + ", to_scene_reference: !<GroupTransform> {children: [" +
                  next + ", " + next + "]}}\n";
    }
    spaces += "  - !<ColorSpace> {name: c" + std::to_string(levels) + ", to_scene_reference: !<MatrixTransform> {}}\n";
    const std::string path = write_config(dir, config_text(spaces));
    std::string m = refusal(path, "c0");
    expect_one_line_naming(m, path);
    EXPECT_TRUE(has(m, "expands to more than 4096 transforms")) << m;
    // Found by npf_fuzz_ocio_config: the same when the last space has no transform at all (OCIO
    // still builds no-ops for each of the 2^n conversions; 2^15 took it past 20 s).
    spaces.replace(spaces.find(", to_scene_reference: !<MatrixTransform> {}"), std::string(", to_scene_reference: !<MatrixTransform> {}").size(), "");
    const std::string empty_last = write_config(npf::testing::temporary_folder("hostile_doubling_empty"), config_text(spaces));
    m = refusal(empty_last, "c0");
    expect_one_line_naming(m, empty_last);
    EXPECT_TRUE(has(m, "expands to more than 4096 transforms")) << m;
}

// A context variable holding itself: OCIO resolves by unbounded recursion, doubling the string
// at each step. Defined in the config (validate() refuses that, but npf's own walk resolves
// first) or, for a config without an environment section, in the process environment.
TEST(ColorHostile, ContextVariablesThatNeverSettleAreRefused) {
    const std::string dir = npf::testing::temporary_folder("hostile_context");
    const std::string space = "  - !<ColorSpace> {name: A, to_scene_reference: !<ColorSpaceTransform> {src: $NPF_GROW, dst: scene}}\n";
    const std::string path = write_config(dir, config_text(space, "environment: {NPF_GROW: $NPF_GROW$NPF_GROW}\n"));
    std::string m = refusal(path, "A");
    expect_one_line_naming(m, path);
    EXPECT_TRUE(has(m, "context variables in the ColorSpaceTransform source '$NPF_GROW' do not settle")) << m;

    const std::string from_env = write_config(npf::testing::temporary_folder("hostile_context_env"), config_text(space));
    ASSERT_EQ(::setenv("NPF_GROW", "$NPF_GROW$NPF_GROW", 1), 0);
    m = error_of([&] { list_display_views(from_env); });
    ::unsetenv("NPF_GROW");
    expect_one_line_naming(m, from_env);
    EXPECT_TRUE(has(m, "context variables in the ColorSpaceTransform source '$NPF_GROW' do not settle")) << m;
}

// 4096 variables over 4096 references: OCIO's validate() resolves each against all (2.5 s).
TEST(ColorHostile, ContextVariablesTooCostlyToResolveAreRefused) {
    const std::string dir = npf::testing::temporary_folder("hostile_context_rounds");
    std::string environment = "environment:\n", references;
    for (std::size_t i = 0; i < kMaxConfigListEntries; ++i) {
        environment += "  V" + std::to_string(i) + ": scene\n";
        references += "        - !<ColorSpaceTransform> {src: $V" + std::to_string(i) + ", dst: scene}\n";
    }
    const std::string path = write_config(dir, config_text(
        "  - !<ColorSpace>\n    name: A\n    to_scene_reference: !<GroupTransform>\n      children:\n" + references, environment));
    const std::string m = error_of([&] { list_display_views(path); });
    expect_one_line_naming(m, path);
    EXPECT_TRUE(has(m, "resolving its context variables (4096) in its references takes more than 4194304 rounds: refused")) << m;
}

// ---------------------------------------------------------------------------------------------
// Size: OCIO's load time grows with the square of the names; aliases are read as copies

TEST(ColorHostile, ConfigsWithTooManyNamesAreRefused) {
    const std::string dir = npf::testing::temporary_folder("hostile_names");
    std::string spaces;
    for (std::size_t i = 0; i < kMaxConfigNames / 3 + 1; ++i) {
        const std::string n = std::to_string(i);
        spaces += "  - !<ColorSpace> {name: c" + n + ", aliases: [x" + n + ", y" + n + "]}\n";
    }
    const std::string path = write_config(dir, config_text(spaces));  // 1366 * 3 + 'scene'
    const std::string m = error_of([&] { list_display_views(path); });
    expect_one_line_naming(m, path);
    EXPECT_TRUE(has(m, "names 4099 colour spaces, named transforms and aliases, above npf's cap of 4096")) << m;
    // One list above its cap.
    spaces.clear();
    for (std::size_t i = 0; i < kMaxConfigListEntries; ++i) spaces += "  - !<ColorSpace> {name: c" + std::to_string(i) + "}\n";
    const std::string long_list = write_config(npf::testing::temporary_folder("hostile_list"), config_text(spaces));
    EXPECT_TRUE(has(error_of([&] { list_display_views(long_list); }), "a YAML list or map (line 10) has 4097 entries"));
}

TEST(ColorHostile, AliasesExpandingBeyondTheCapAreRefused) {
    const std::string dir = npf::testing::temporary_folder("hostile_aliases");
    std::string anchors = "npf_anchors:\n  - &g0 !<MatrixTransform> {}\n";
    for (int i = 1; i <= 20; ++i)
        anchors += "  - &g" + std::to_string(i) + " !<GroupTransform> {children: [*g" + std::to_string(i - 1) + ", *g" +
                   std::to_string(i - 1) + "]}\n";
    const std::string path = write_config(dir, config_text("  - !<ColorSpace> {name: A, to_scene_reference: *g20}\n", anchors));
    const std::string m = error_of([&] { list_display_views(path); });
    expect_one_line_naming(m, path);
    EXPECT_TRUE(has(m, "its YAML expands to more than 1048576 nodes")) << m;
}

// OCIO compiles file rules with std::regex at load: its compiler recursed until SIGSEGV.
TEST(ColorHostile, FileRulesLongerThanTheCapAreRefused) {
    const std::string dir = npf::testing::temporary_folder("hostile_file_rule");
    std::string text = config_text("");
    const std::string rule = "  - !<Rule> {name: Default, colorspace: default}\n";
    text.replace(text.find(rule), rule.size(),
                 "  - !<Rule> {name: deep, colorspace: scene, regex: \"" + std::string(20000, '(') + "a" + std::string(20000, ')') +
                     "\"}\n" + rule);
    const std::string path = write_config(dir, text);
    std::string m = error_of([&] { list_display_views(path); });
    expect_one_line_naming(m, path);
    EXPECT_TRUE(has(m, "a file rule's regex (line 5) has 40001 characters, above npf's cap of 1024")) << m;
    // A glob is turned into a regex too.
    text = config_text("");
    text.replace(text.find(rule), rule.size(),
                 "  - !<Rule> {name: stars, colorspace: scene, pattern: \"" + std::string(2000, '*') + "\", extension: exr}\n" + rule);
    const std::string glob = write_config(npf::testing::temporary_folder("hostile_file_rule_glob"), text);
    m = error_of([&] { list_display_views(glob); });
    EXPECT_TRUE(has(m, "a file rule's pattern (line 5) has 2000 characters")) << m;
}

// The config itself is read within kConfigTextBounds (before: OCIO read /dev/zero or a FIFO
// without end).
TEST(ColorHostile, ConfigThatIsNotARegularFileIsRefused) {
    const std::string dir = npf::testing::temporary_folder("hostile_config_file");
    const std::string fifo = (fs::path(dir) / "fifo.ocio").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    for (const std::string& path : {fifo, std::string("/dev/zero")}) {
        const std::string m = error_of([&] { list_display_views(path); });
        expect_one_line_naming(m, path);
        EXPECT_TRUE(has(m, "regular file")) << m;
    }
}

// ---------------------------------------------------------------------------------------------
// OCIO's reason, always

TEST(ColorHostile, SanityCheckFailureCarriesTheReason) {
    const std::string dir = npf::testing::temporary_folder("hostile_sanity");
    const std::string path = write_config(dir, config_text(
        "  - !<ColorSpace> {name: lut, to_scene_reference: !<FileTransform> {src: grade.cube}}\n", "", "", ""));
    const std::string m = error_of([&] { list_display_views(path); });
    expect_one_line_naming(m, path);
    EXPECT_TRUE(has(m, "Config failed sanitycheck. (it names the LUT 'grade.cube' but has no search_path to find it in)")) << m;
}

// ---------------------------------------------------------------------------------------------
// LUTs (FileTransform): regular files, bounded, under the config's search path

struct LutConfig {
    std::string dir, path;
};

// A config in a fresh folder with search_path 'luts' and colour space 'lut' whose transform to
// the scene reference is the FileTransform `src`.
LutConfig lut_config(const std::string& tag, const std::string& src) {
    LutConfig c;
    c.dir = npf::testing::temporary_folder(tag);
    fs::create_directories(fs::path(c.dir) / "luts");
    c.path = write_config(c.dir, config_text(
        "  - !<ColorSpace> {name: lut, to_scene_reference: !<FileTransform> {src: \"" + src + "\", interpolation: linear}}\n"));
    return c;
}

const std::string kHalvingCube = "LUT_1D_SIZE 2\n0 0 0\n0.5 0.5 0.5\n";

TEST(ColorHostile, LutInTheSearchPathWorksAsBefore) {
    const LutConfig c = lut_config("hostile_lut_good", "half.cube");
    write_file(c.dir + "/luts/half.cube", kHalvingCube);
    const auto v = from_space(c.path, "lut").apply({0.8, 0.4, 0.2});
    EXPECT_NEAR(v[0], 0.4, 1e-6);
    EXPECT_NEAR(v[1], 0.2, 1e-6);
    EXPECT_NEAR(v[2], 0.1, 1e-6);
    // A link inside the search path to a file inside it, and a sub-folder.
    const LutConfig linked = lut_config("hostile_lut_link_inside", "sub/link.cube");
    write_file(linked.dir + "/luts/half.cube", kHalvingCube);
    fs::create_directories(linked.dir + "/luts/sub");
    fs::create_symlink("../half.cube", linked.dir + "/luts/sub/link.cube");
    EXPECT_NEAR(from_space(linked.path, "lut").apply({0.8, 0.4, 0.2})[0], 0.4, 1e-6);
    // Relative search paths start at the config's folder, not the working directory.
    const std::string cwd = fs::current_path().string();
    ASSERT_EQ(::chdir("/"), 0);
    std::string problem;
    try {
        EXPECT_NEAR(from_space(c.path, "lut").apply({0.8, 0.4, 0.2})[0], 0.4, 1e-6);
    } catch (const npf::Error& e) {
        problem = e.what();
    }
    ASSERT_EQ(::chdir(cwd.c_str()), 0);
    EXPECT_EQ(problem, "");
}

TEST(ColorHostile, MissingLutIsNamed) {
    const LutConfig c = lut_config("hostile_lut_missing", "missing.cube");
    const std::string m = refusal(c.path, "lut");
    expect_one_line_naming(m, c.path);
    EXPECT_TRUE(has(m, "LUT 'missing.cube' not found in the search path ('" + c.dir + "/luts')")) << m;
}

TEST(ColorHostile, LutThatIsAFifoIsRefusedWithoutWaiting) {
    const LutConfig c = lut_config("hostile_lut_fifo", "fifo.cube");
    ASSERT_EQ(::mkfifo((c.dir + "/luts/fifo.cube").c_str(), 0600), 0);
    const std::string m = refusal(c.path, "lut");
    expect_one_line_naming(m, c.path);
    EXPECT_TRUE(has(m, "fifo.cube) is a FIFO, not a regular file: refused")) << m;
}

TEST(ColorHostile, LutThatIsDevZeroIsRefused) {
    const LutConfig c = lut_config("hostile_lut_zero", "zero.cube");
    fs::create_symlink("/dev/zero", c.dir + "/luts/zero.cube");
    std::string m = refusal(c.path, "lut");
    expect_one_line_naming(m, c.path);
    EXPECT_TRUE(has(m, "zero.cube) is a character device, not a regular file: refused")) << m;
    const LutConfig absolute = lut_config("hostile_lut_zero_abs", "/dev/zero");
    m = refusal(absolute.path, "lut");
    EXPECT_TRUE(has(m, "LUT '/dev/zero' (/dev/zero) is a character device")) << m;
}

TEST(ColorHostile, LutThatIsAFolderIsRefused) {
    const LutConfig c = lut_config("hostile_lut_folder", "folder.cube");
    fs::create_directories(c.dir + "/luts/folder.cube");
    const std::string m = refusal(c.path, "lut");
    expect_one_line_naming(m, c.path);
    EXPECT_TRUE(has(m, "folder.cube) is a folder, not a regular file: refused")) << m;
}

TEST(ColorHostile, LutAboveTheSizeCapIsRefused) {
    const LutConfig c = lut_config("hostile_lut_huge", "huge.cube");
    const std::string huge = c.dir + "/luts/huge.cube";
    write_file(huge, kHalvingCube);
    ASSERT_EQ(::truncate(huge.c_str(), static_cast<off_t>(kMaxLutBytes + 1)), 0);  // sparse: no disk used
    const std::string m = refusal(c.path, "lut");
    expect_one_line_naming(m, c.path);
    EXPECT_TRUE(has(m, "huge.cube) is 268435457 bytes, above npf's cap of 268435456 (256 MiB) for a LUT: refused")) << m;
}

// OCIO builds a table for each use of a LUT: 129 uses of a 2 MiB file are 258 MiB.
TEST(ColorHostile, LutReadsAboveTheSizeCapTogetherAreRefused) {
    const std::string dir = npf::testing::temporary_folder("hostile_lut_uses");
    std::string padded = kHalvingCube;
    while (padded.size() < (std::size_t(2) << 20)) padded += "# " + std::string(1000, 'x') + "\n";
    padded.resize(std::size_t(2) << 20);
    padded.back() = '\n';
    write_file(dir + "/luts/padded.cube", padded);
    std::string uses;
    for (int i = 0; i < 129; ++i) uses += "        - !<FileTransform> {src: padded.cube}\n";
    const std::string path = write_config(dir, config_text(
        "  - !<ColorSpace>\n    name: lut\n    to_scene_reference: !<GroupTransform>\n      children:\n" + uses));
    const std::string m = refusal(path, "lut");
    expect_one_line_naming(m, path);
    EXPECT_TRUE(has(m, "the display transform from 'lut' to 'd' / 'v' reads LUT files 129 times, 270532608 bytes in all, "
                       "above npf's cap of 268435456 (256 MiB): refused")) << m;
}

TEST(ColorHostile, LutsOutsideTheSearchPathAreRefused) {
    // Through '..', by an absolute path, and through a link out of the folder: all to a valid LUT.
    for (const std::string how : {"dotdot", "absolute", "link"}) {
        const std::string tag = "hostile_lut_out_" + how;
        LutConfig c = lut_config(tag, "placeholder");
        write_file(c.dir + "/outside.cube", kHalvingCube);
        std::string src = "../outside.cube";
        if (how == "absolute") src = c.dir + "/outside.cube";
        if (how == "link") {
            src = "link.cube";
            fs::create_symlink(c.dir + "/outside.cube", c.dir + "/luts/link.cube");
        }
        c.path = write_config(c.dir, config_text(
            "  - !<ColorSpace> {name: lut, to_scene_reference: !<FileTransform> {src: \"" + src + "\"}}\n"));
        const std::string m = refusal(c.path, "lut");
        expect_one_line_naming(m, c.path);
        EXPECT_TRUE(has(m, "lies outside the config's search path ('" + c.dir + "/luts'")) << how << ": " << m;
        EXPECT_TRUE(has(m, "it is " + fs::canonical(c.dir + "/outside.cube").string() + "): refused")) << how << ": " << m;
    }
    // '..' that leaves the folder lexically, as OCIO normalises it, though "no/" does not exist.
    LutConfig c = lut_config("hostile_lut_out_lexical", "no/../../outside.cube");
    write_file(c.dir + "/outside.cube", kHalvingCube);
    fs::create_directories(c.dir + "/luts/no");
    const std::string m = refusal(c.path, "lut");
    EXPECT_TRUE(has(m, "lies outside the config's search path")) << m;
}

TEST(ColorHostile, LutSizeClaimsAboveTheFileAreRefused) {
    struct Case {
        std::string name, bytes, expected;
    };
    std::string icc(128, '\0');
    icc[3] = char(132);
    icc.replace(36, 4, "acsp");
    icc += std::string("\x02\xfa\xf0\x80", 4);  // 50,000,000 tags
    const std::vector<Case> cases = {
        {"big3d.cube", "LUT_3D_SIZE 100000\n0 0 0\n", "line 1 claims 3e+15 values (LUT_3D_SIZE 100000) but the file has 25 bytes"},
        {"big1d.cube", "LUT_1D_SIZE 1000000000\n0 0 0\n", "claims 3e+09 values (LUT_1D_SIZE 1e+09)"},
        {"negative.cube", "LUT_3D_SIZE -5\n0 0 0\n", "line 1 claims a negative size"},
        {"long.spi1d", "Version 1\nFrom 0.0 1.0\nLength 1000000000\nComponents 1\n{\n0\n1\n}\n", "line 3 claims 1e+09 values (Length 1e+09)"},
        {"tags.icc", icc, "an ICC profile claiming 50000000 tags (12 bytes each) in 132 bytes"},
        {"index.clf",
         "<?xml version=\"1.0\"?>\n<ProcessList id=\"x\" compCLFversion=\"3\">\n<LUT1D inBitDepth=\"32f\" outBitDepth=\"32f\">\n"
         "<IndexMap dim=\"100000000\">0@0 1@1</IndexMap>\n<Array dim=\"2 1\">\n0\n1\n</Array>\n</LUT1D>\n</ProcessList>\n",
         "dim=\"100000000\" claims 1e+08 values"},
        {"matrix.ctf",
         "<?xml version=\"1.0\"?>\n<ProcessList id=\"x\" version=\"1.2\">\n<Matrix inBitDepth=\"32f\" outBitDepth=\"32f\">\n"
         "<Array dim=\"10000 10000 3\">\n1 0 0\n0 1 0\n0 0 1\n</Array>\n</Matrix>\n</ProcessList>\n",
         "dim=\"10000 10000 3\" claims 3e+08 values"},
        // OCIO tries every reader on a file its own reader fails on: the claim counts whatever the name.
        {"tags_named.cube", icc, "an ICC profile claiming 50000000 tags"},
        {"token.spi1d", "Version 1\nFrom 0.0 " + std::string(100, '1') + "\nLength 2\nComponents 1\n{\n0\n1\n}\n",
         "line 2 has a token of 100 characters"},
    };
    for (const Case& k : cases) {
        const LutConfig c = lut_config("hostile_lut_claims", k.name);
        write_file(c.dir + "/luts/" + k.name, k.bytes);
        const std::string m = refusal(c.path, "lut");
        expect_one_line_naming(m, c.path);
        EXPECT_TRUE(has(m, "LUT '" + k.name + "'") && has(m, k.expected) && has(m, ": refused")) << k.name << ": " << m;
    }
}

// ---------------------------------------------------------------------------------------------
// The tool: status 1 and one line (a reference cycle ended it with SIGSEGV, status 139)

TEST(ColorHostile, ToolRefusesACyclicConfigWithStatusOne) {
    const std::string dir = npf::testing::temporary_folder("hostile_cli");
    // The cycle is in the scene_linear space, which `npf display` converts from by default.
    const std::string config = write_config(dir,
        "ocio_profile_version: 2.1\n"
        "roles: {default: A, scene_linear: A}\n"
        "file_rules:\n  - !<Rule> {name: Default, colorspace: default}\n"
        "displays:\n  d:\n    - !<View> {name: v, colorspace: out}\n"
        "colorspaces:\n"
        "  - !<ColorSpace> {name: out}\n"
        "  - !<ColorSpace> {name: A, to_scene_reference: !<ColorSpaceTransform> {src: B, dst: out}}\n"
        "  - !<ColorSpace> {name: B, to_scene_reference: !<ColorSpaceTransform> {src: A, dst: out}}\n");
    const std::string exr = dir + "/in.exr", png = dir + "/out.png";
    {
        OIIO::ImageSpec spec(1, 1, 3, OIIO::TypeFloat);
        const float px[3] = {0.18f, 0.18f, 0.18f};
        auto out = OIIO::ImageOutput::create(exr);
        ASSERT_TRUE(out && out->open(exr, spec) && out->write_image(OIIO::TypeFloat, px) && out->close());
    }
    const npf::testing::ToolRun r = npf::testing::run_tool({"display", exr, "-o", png, "--config", config});
    EXPECT_EQ(r.status, 1) << npf::testing::describe(r);
    EXPECT_EQ(npf::testing::lines_of(r.err).size(), 1u) << npf::testing::describe(r);
    EXPECT_TRUE(has(r.err, config) && has(r.err, "colour space 'A' refers to itself through colour space 'B'"))
        << npf::testing::describe(r);
    EXPECT_FALSE(fs::exists(png));
}

}  // namespace
