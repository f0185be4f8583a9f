// npf display IN.exr -o OUT.png: a scene-referred image (linear Rec.709 or CIE XYZ) to a
// display-encoded 8-bit PNG through OpenColorIO; --list shows the config's displays and views.
#include "command_line.h"
#include "commands.h"
#include "file_uses.h"
#include "scene_space_flag.h"

#include <npf/color/display.h>
#include <npf/color/display_image.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>

#include <cstdio>
#include <optional>
#include <string>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = flag_table({
    "-o VALUE  output PNG (8-bit, display-encoded), required unless --list",
    "--from VALUE  what the input holds: linear (Rec.709 / sRGB primaries, default) or xyz (CIE XYZ D65)",
    "--config VALUE  OpenColorIO config (default: $OCIO, else the config npf ships)",
    "--display VALUE  display (default: the config's default)",
    "--view VALUE  view (default: the display's default)",
    "--list  print the config's displays and views and exit",
});

const char* kHelp =
    "usage: npf display IN.exr -o OUT.png [--from linear|xyz] [--config FILE] [--display NAME]\n"
    "                   [--view NAME]\n"
    "       npf display --list [--config FILE]\n\n"
    "Writes a scene-referred image (any file OpenImageIO reads; its first three channels, and\n"
    "alpha) as an 8-bit PNG through an OpenColorIO display and view (docs/color.md).\n\n";

int list(const std::string& config) {
    const std::vector<color::DisplayViews> displays = color::list_display_views(config);  // may throw
    std::printf("config: %s\n", color::resolve_ocio_config_path(config).c_str());
    bool first_display = true;
    for (const color::DisplayViews& d : displays) {
        std::printf("display: %s%s\n", d.display.c_str(), first_display ? " (default)" : "");
        for (std::size_t i = 0; i < d.views.size(); ++i)
            std::printf("  view: %s%s\n", d.views[i].c_str(), i == 0 ? " (default)" : "");
        first_display = false;
    }
    return 0;
}

}  // namespace

int run_display(const std::vector<std::string>& args) {
    const CommandLine cl = read_command_line(kHelp, kFlags, args);
    if (cl.has("--list")) return list(cl.value("--config"));
    cl.expect_positional(1, 1, "one IN.exr");
    cl.require("-o");
    color::DisplayOptions options;
    options.input = scene_space_flag(cl);
    options.config_path = cl.value("--config");
    options.display = cl.value("--display");
    options.view = cl.value("--view");
    const color::DisplayTransform transform(options);  // before reading: a bad flag fails fast
    FileUses uses;
    uses.input(cl.positional()[0], "the input");
    if (!options.config_path.empty()) uses.input(options.config_path, "--config");
    uses.output(cl.value("-o"), "-o").check();
    check_output_path(cl.value("-o"));
    const color::FloatImage image = color::read_scene_image(cl.positional()[0]);
    color::write_display_png(cl.value("-o"), image, transform);
    return 0;
}

}  // namespace npf::cli
