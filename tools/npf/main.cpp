// npf: convert, inspect and evaluate measured BRDFs. One command, one subcommand per task.
#include "command_line.h"
#include "commands.h"

#include <npf/core/error.h>
#include <npf/core/version.h>

#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

// The library versions npf was built with, where a header says so cheaply (yaml-cpp has no
// version macro). The tool target does not always see these headers: each is optional.
#if __has_include(<OpenImageIO/oiioversion.h>)
#include <OpenImageIO/oiioversion.h>
#endif
#if __has_include(<OpenEXR/OpenEXRConfig.h>)
#include <OpenEXR/OpenEXRConfig.h>
#endif
#if __has_include(<OpenColorIO/OpenColorABI.h>)
#include <OpenColorIO/OpenColorABI.h>
#endif
#if __has_include(<Eigen/src/Core/util/Macros.h>)
#include <Eigen/src/Core/util/Macros.h>
#elif __has_include(<eigen3/Eigen/src/Core/util/Macros.h>)
#include <eigen3/Eigen/src/Core/util/Macros.h>
#endif


namespace {

struct Subcommand {
    const char* name;
    int (*run)(const std::vector<std::string>&);
    const char* summary;
};

const Subcommand kSubcommands[] = {
    {"info", npf::cli::run_info, "what a material file holds: format, isotropy, channels, grids, size"},
    {"eval", npf::cli::run_eval, "evaluate a material at direction pairs read from a file or stdin"},
    {"convert", npf::cli::run_convert, "fit the NPF factors to a material and write the factor texture (.exr)"},
    {"synth", npf::cli::run_synth, "write an RGL .bsdf file from an analytic material (recipe or flags)"},
    {"bench", npf::cli::run_bench, "time shading with an NPF texture (eval, sample, pdf) against its source"},
    {"display", npf::cli::run_display, "write a scene-linear or XYZ image as a display-encoded PNG (OpenColorIO)"},
    {"render", npf::cli::run_render, "path-trace a material on the Sphere scene under an environment map"},
    {"albedo", npf::cli::run_albedo, "directional albedo against view angle; with two materials, where they differ"},
    {"compare", npf::cli::run_compare, "PSNR, SSIM, relMSE and MAPE of a test image against a reference"},
    {"edit", npf::cli::run_edit, "edit a fitted material: NDF transforms, diffuse/specular colour, thin-film Fresnel"},
    {"batch", npf::cli::run_batch, "convert a material library from a YAML batch: resumable, shardable, failure-isolated"},
};

void print_usage(std::FILE* to) {
    std::fprintf(to, "usage: npf <command> [options]\n\ncommands:\n");
    for (const Subcommand& s : kSubcommands) std::fprintf(to, "  %-8s %s\n", s.name, s.summary);
    std::fprintf(to, "\n'npf <command> --help' describes a command; 'npf --version' prints the versions.\n");
}

#define NPF_STR2(x) #x
#define NPF_STR(x) NPF_STR2(x)

void print_version() {
    std::string libraries;
    const auto add = [&](const char* name, const std::string& version) {
        libraries += (libraries.empty() ? "built with " : ", ") + std::string(name) + " " + version;
    };
#ifdef OIIO_VERSION_STRING
    add("OpenImageIO", OIIO_VERSION_STRING);
#endif
#ifdef OPENEXR_VERSION_STRING
    add("OpenEXR", OPENEXR_VERSION_STRING);
#endif
#ifdef OCIO_VERSION_STR
    add("OpenColorIO", OCIO_VERSION_STR);
#endif
#ifdef EIGEN_WORLD_VERSION
    add("Eigen", NPF_STR(EIGEN_WORLD_VERSION) "." NPF_STR(EIGEN_MAJOR_VERSION) "." NPF_STR(EIGEN_MINOR_VERSION));
#endif
    std::printf("npf %s\n", npf::version());
    if (!libraries.empty()) std::printf("%s\n", libraries.c_str());
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
        print_usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    if (!std::strcmp(argv[1], "--version")) {
        print_version();
        return 0;
    }
    const std::string name = argv[1];
    std::vector<std::string> args(argv + 2, argv + argc);
    for (const Subcommand& s : kSubcommands) {
        if (name != s.name) continue;
        try {
            return s.run(args);
        } catch (const npf::cli::VersionRequest&) {
            print_version();
            return 0;
        } catch (const npf::cli::HelpRequest& help) {
            std::fputs(help.text.c_str(), stdout);
            return 0;
        } catch (const npf::cli::UsageError& e) {
            std::fprintf(stderr, "npf %s: error: %s (see npf %s --help)\n", s.name, e.what(), s.name);
            // A bare command also shows its usage on stdout, as --help does (scripts and
            // tests rely on that); the error line above says what was missing.
            if (args.empty()) {
                try {
                    s.run({"--help"});
                } catch (const npf::cli::HelpRequest& help) {
                    std::fputs(help.text.c_str(), stdout);
                } catch (const std::exception&) {
                }
            }
            return e.status();
        } catch (const npf::Error& e) {
            std::fprintf(stderr, "npf %s: error: %s\n", s.name, e.what());
            return 1;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "npf %s: internal error: %s\n", s.name, e.what());
            return 3;
        }
    }
    std::fprintf(stderr, "npf: unknown command '%s'\n\n", name.c_str());
    print_usage(stderr);
    return 2;
}
