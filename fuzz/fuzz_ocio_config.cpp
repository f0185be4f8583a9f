// libFuzzer target: an OpenColorIO config through npf's loading path (docs/color.md, "Hostile
// configs"): the bounded read, the YAML, graph and context-variable checks, OCIO's parse and
// validate (list_display_views), then for a few displays and views a DisplayTransform (the
// LUT checks and OCIO's processor) applied to a few pixels.
//
// The input is written as config.ocio into a scratch folder made at start, whose luts/ holds
// LUTs for FileTransforms to name: small valid ones (.cube 1D and 3D, .spi1d, .clf) and hostile
// ones (a FIFO, a folder, a link out of the folder, a file claiming a 100000^3 grid); the seeds
// (fuzz/corpus/ocio_config/) name them. OpenColorIO and yaml-cpp are the system's,
// uninstrumented: coverage guides the fuzzer through npf's checks only.
#include <npf/color/display.h>
#include <npf/core/error.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

std::string g_dir, g_config;  // the scratch folder, its config.ocio

void remove_scratch() {
    std::error_code ec;
    std::filesystem::remove_all(g_dir, ec);
}

void put(const std::string& path, const std::string& text) {
    if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
        std::fwrite(text.data(), 1, text.size(), f);
        std::fclose(f);
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // OCIO logs warnings (unknown keys, ...) to stderr for every input; they cost time, not bugs.
    ::setenv("OCIO_LOGGING_LEVEL", "none", 1);
    ::unsetenv("OCIO");
    std::string dir = "/dev/shm";
    if (::access(dir.c_str(), W_OK) != 0) {
        const char* t = std::getenv("TMPDIR");
        dir = t && *t ? t : "/tmp";
    }
    dir += "/npf-fuzz-ocio-" + std::to_string(::getpid());
    const std::string luts = dir + "/luts";
    ::mkdir(dir.c_str(), 0700);
    g_dir = dir;
    std::atexit(remove_scratch);
    ::mkdir(luts.c_str(), 0700);
    put(luts + "/half.cube", "LUT_1D_SIZE 2\n0 0 0\n0.5 0.5 0.5\n");
    std::string grid = "LUT_3D_SIZE 2\n";
    for (int i = 0; i < 8; ++i) grid += std::to_string(i & 1) + " " + std::to_string((i >> 1) & 1) + " " + std::to_string(i >> 2) + "\n";
    put(luts + "/grid.cube", grid);
    put(luts + "/lin.spi1d", "Version 1\nFrom 0.0 1.0\nLength 2\nComponents 1\n{\n0\n1\n}\n");
    put(luts + "/m.clf",
        "<?xml version=\"1.0\"?>\n<ProcessList id=\"m\" compCLFversion=\"3\">\n"
        "<Matrix inBitDepth=\"32f\" outBitDepth=\"32f\"><Array dim=\"3 3\">\n0.5 0 0\n0 0.5 0\n0 0 0.5\n</Array></Matrix>\n"
        "</ProcessList>\n");
    put(luts + "/claims.cube", "LUT_3D_SIZE 100000\n0 0 0\n");
    put(dir + "/outside.cube", "LUT_1D_SIZE 2\n0 0 0\n1 1 1\n");
    ::symlink("../outside.cube", (luts + "/out.cube").c_str());
    ::mkdir((luts + "/dir.cube").c_str(), 0700);
    ::mkfifo((luts + "/fifo.cube").c_str(), 0600);
    g_config = dir + "/config.ocio";
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    put(g_config, std::string(reinterpret_cast<const char*>(data), size));
    try {
        const std::vector<npf::color::DisplayViews> displays = npf::color::list_display_views(g_config);
        int built = 0;
        for (const npf::color::DisplayViews& d : displays) {
            for (const std::string& view : d.views) {
                if (built++ == 3) return 0;  // enough of one config: each transform loads it again
                for (npf::color::SceneSpace input : {npf::color::SceneSpace::LinearRec709, npf::color::SceneSpace::CieXyzD65}) {
                    try {
                        npf::color::DisplayOptions o;
                        o.config_path = g_config;
                        o.display = d.display;
                        o.view = view;
                        o.input = input;
                        const npf::color::DisplayTransform t(o);
                        float pixels[12] = {0.18f, 0.18f, 0.18f, 1.0f, 0.5f, 0.0f, -1.0f, 4.0f, 1e30f, 0.0f, 0.0f, 0.0f};
                        t.apply(pixels, 2, 2, 3);
                        (void)t.apply({0.5, 0.25, 0.125});
                    } catch (const npf::Error&) {
                        // e.g. no XYZ space in this config, a LUT refused: the next one
                    }
                }
            }
        }
    } catch (const npf::Error&) {
        // Refused with a message: what a loader should do with a bad config.
    }
    return 0;
}
