// Texture farms over factor textures (docs/farms.md), with the real maketx, oiiotool and iinfo:
// the documented workflow leaves every factor texture byte-identical and shading exactly as
// before, and whatever the tools make of a factor texture either shades exactly as the original
// or is refused, by NpfClosure on both paths and by `npf info --check`, with one line naming the
// file and the problem. The tools are required: without them these tests fail (CI installs
// openimageio-tools, scripts/install-deps.sh).
#include "npf_test_factors.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/fit/spectral_compression.h>
#include <npf/core/error.h>
#include <npf/shading/npf_closure.h>
#include <npf/shading/npf_texture_file.h>

#include <OpenImageIO/imageio.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <sys/wait.h>

namespace {

namespace fs = std::filesystem;
using npf::NpfClosure, npf::testing::contains, npf::testing::describe, npf::testing::shell_quote,
      npf::testing::ToolRun;

// ---- The tools and the shell ----------------------------------------------------------------

void require_image_tools() {
    for (const char* tool : {"maketx", "oiiotool", "iinfo"}) {
        const std::string probe = std::string("command -v ") + tool + " > /dev/null 2>&1";
        ASSERT_EQ(std::system(probe.c_str()), 0)
            << tool << " is not installed: these tests need OpenImageIO's tools (Debian: openimageio-tools, which "
            << "scripts/install-deps.sh installs)";
    }
}

struct ShellRun {
    int status = -1;
    std::string log;  // stdout and stderr
};

// Runs `command` with bash in `dir`, with the npf under test first on the PATH.
ShellRun shell(const std::string& command, const std::string& dir) {
    const std::string log = dir + "/.shell.log";
    const std::string tools = fs::path(NPF_TOOL_PATH).parent_path().string();
    const std::string line = "cd " + shell_quote(dir) + " && PATH=" + shell_quote(tools) + ":\"$PATH\" bash -c " +
                             shell_quote(command) + " > " + shell_quote(log) + " 2>&1";
    const int raw = std::system(line.c_str());
    ShellRun r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.log = npf::testing::read_text(log);
    fs::remove(log);
    return r;
}

std::string bytes_of(const std::string& path) { return npf::testing::read_text(path); }

// ---- What a factor texture shades -------------------------------------------------------------

// Everything a renderer gets from the file on one path: eval (values and pdf) and sample (the
// drawn direction, its pdf and weights) at fixed pairs, every stored channel.
std::vector<float> shading_of(const std::string& path, NpfClosure::Path kind) {
    const NpfClosure closure(path, kind);
    const npf::WavelengthRequest stored = npf::WavelengthRequest::stored();
    std::vector<float> out, values(closure.value_count(stored));
    const auto direction = [](double theta, double phi) {
        return npf::Vec3(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                         float(std::cos(theta)));
    };
    for (int i = 0; i < 48; ++i) {
        const npf::Vec3 view = direction(1.45 * (i % 8 + 0.5) / 8, 0.7 + 0.37 * i);
        const npf::Vec3 light = direction(1.45 * (i / 8 + 0.5) / 6, 2.1 - 0.53 * i);
        out.push_back(closure.eval(view, light, stored, values.data()));
        out.insert(out.end(), values.begin(), values.end());
        npf::ClosureSample s;
        const bool drawn = closure.sample(view, (i % 7 + 0.5f) / 7, (i % 5 + 0.5f) / 5, stored, s, values.data());
        out.push_back(drawn ? 1.f : 0.f);
        out.insert(out.end(), {s.light.x, s.light.y, s.light.z, s.pdf});
        out.insert(out.end(), values.begin(), values.end());
    }
    return out;
}

struct Shading {
    std::vector<float> memory, texture;
};

Shading shading_of(const std::string& path) {
    return {shading_of(path, NpfClosure::Path::Memory), shading_of(path, NpfClosure::Path::Texture)};
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// `path` loads on both paths and evaluates to exactly `original`'s values.
void expect_closures_shade_as(const std::string& path, const Shading& original) {
    Shading got;
    try {
        got = shading_of(path);
    } catch (const npf::Error& e) {
        ADD_FAILURE() << path << " does not load: " << e.what();
        return;
    }
    EXPECT_TRUE(same_bits(got.memory, original.memory)) << path << " shades differently (memory path)";
    EXPECT_TRUE(same_bits(got.texture, original.texture)) << path << " shades differently (texture path)";
}

// NpfClosure refuses `path` on both paths: one line that names it and says `because` ("" for any
// reason).
void expect_closures_refuse(const std::string& path, const std::string& because) {
    for (NpfClosure::Path kind : {NpfClosure::Path::Memory, NpfClosure::Path::Texture}) {
        const char* name = kind == NpfClosure::Path::Memory ? "memory" : "texture";
        try {
            const NpfClosure closure(path, kind);
            ADD_FAILURE() << path << " was loaded on the " << name << " path";
        } catch (const npf::Error& e) {
            const std::string what = e.what();
            EXPECT_EQ(e.source(), path) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << "not one line: " << what;
            EXPECT_TRUE(contains(what, because)) << name << " path: " << what << "\nexpected: " << because;
        }
    }
}

// The same, and `npf info --check` agrees.
void expect_shades_as(const std::string& path, const Shading& original) {
    expect_closures_shade_as(path, original);
    const ToolRun check = npf::testing::run_tool({"info", "--check", path});
    EXPECT_EQ(check.status, 0) << describe(check);
    EXPECT_EQ(check.out, "ok: " + path + "\n") << describe(check);
}

void expect_refused(const std::string& path, const std::string& because) {
    expect_closures_refuse(path, because);
    const ToolRun check = npf::testing::run_tool({"info", "--check", path});
    EXPECT_EQ(check.status, 1) << describe(check);
    const std::vector<std::string> lines = npf::testing::lines_of(check.out);
    ASSERT_EQ(lines.size(), 1u) << describe(check);
    EXPECT_EQ(lines[0].rfind("error: " + path + ": ", 0), 0u) << describe(check);
    EXPECT_TRUE(contains(lines[0], because)) << describe(check);
    EXPECT_EQ(check.err, "npf info: error: 1 of 1 file would not shade\n") << describe(check);
}

// ---- The factor textures of the folder --------------------------------------------------------

struct FactorTexture {
    std::string name;
    bool sealed;  // has npf:tables_checksum (written by this version)
    std::string path;
    Shading shading;
};

// Written once: a conversion by the tool (RGB, isotropic, with the half-precision detail layer),
// an anisotropic spectral model written here (no detail layer, format version 1), and two files
// written before npf:tables_checksum existed (testsuite/farm-safety/unsealed/).
const std::vector<FactorTexture>& factor_textures() {
    static const std::vector<FactorTexture> textures = [] {
        const std::string dir = npf::testing::temporary_folder("farm-originals");
        std::vector<FactorTexture> t;
        const std::string recipe = std::string(NPF_SOURCE_DIR) + "/configs/materials/red_plastic.yaml";
        const ToolRun convert =
            npf::testing::run_tool({"convert", recipe, "-o", dir + "/red_plastic.exr", "--wavelengths", "rgb", "--preset",
                                    "preview", "--no-predict", "--error-pairs", "0", "--quiet"});
        if (convert.status != 0) throw npf::Error(dir, "npf convert failed: " + describe(convert));
        t.push_back({"red_plastic.exr", true, dir + "/red_plastic.exr", {}});

        npf::CompressionOptions o;
        o.d_rank = 4;
        o.g_rank = 3;
        npf::write_npf_texture(npf::compress_factors(npf::testing::make_test_factors({true, 20, true, 5}), o),
                               dir + "/aniso_spectral.exr");
        t.push_back({"aniso_spectral.exr", true, dir + "/aniso_spectral.exr", {}});

        for (const char* old : {"v2-rgb-detail.exr", "v1-spectral-aniso.exr"}) {
            const std::string path = dir + "/unsealed-" + old;
            fs::copy_file(std::string(NPF_SOURCE_DIR) + "/testsuite/farm-safety/unsealed/" + old, path);
            t.push_back({std::string("unsealed-") + old, false, path, {}});
        }
        for (FactorTexture& f : t) f.shading = shading_of(f.path);
        return t;
    }();
    return textures;
}

// An ordinary image texture, for the farm's loop to process.
void write_image_texture(const std::string& path) {
    const int w = 8, h = 8;
    std::vector<float> pixels(std::size_t(w * h * 3));
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = float(i % 17) / 16.f;
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path, OIIO::ImageSpec(w, h, 3, OIIO::TypeFloat))) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeFloat, pixels.data())) << out->geterror();
    ASSERT_TRUE(out->close()) << out->geterror();
}

// The block docs/farms.md marks as the one this test runs.
std::string documented_workflow() {
    const std::string doc = npf::testing::read_text(std::string(NPF_SOURCE_DIR) + "/docs/farms.md");
    const std::size_t marker = doc.find("<!-- tools/npf/tests/test_farm_safety.cpp runs the next block");
    const std::size_t begin = doc.find("```sh\n", marker);
    const std::size_t end = doc.find("```\n", begin + 6);
    if (marker == std::string::npos || begin == std::string::npos || end == std::string::npos) return "";
    return doc.substr(begin + 6, end - begin - 6);
}

// ---- The tests --------------------------------------------------------------------------------

TEST(FarmSafety, DocumentedWorkflowLeavesEveryFactorTextureShadingAsBefore) {
    ASSERT_NO_FATAL_FAILURE(require_image_tools());
    const std::string workflow = documented_workflow();
    ASSERT_FALSE(workflow.empty()) << "docs/farms.md has no marked workflow block";
    const std::string dir = npf::testing::temporary_folder("farm-workflow");
    std::map<std::string, std::string> before;
    for (const FactorTexture& f : factor_textures()) {
        fs::copy_file(f.path, dir + "/" + f.name);
        before[f.name] = bytes_of(f.path);
    }
    ASSERT_NO_FATAL_FAILURE(write_image_texture(dir + "/albedo.exr"));

    // As a farm runs it: strict bash, $TEXTURES the folder.
    ASSERT_TRUE(npf::testing::write_text(dir + "/.farm.sh", workflow));
    const ShellRun run = shell("set -euo pipefail; TEXTURES=" + shell_quote(dir) + "; source .farm.sh", dir);
    ASSERT_EQ(run.status, 0) << run.log;

    for (const FactorTexture& f : factor_textures()) {
        SCOPED_TRACE(f.name);
        const std::string path = dir + "/" + f.name;
        EXPECT_EQ(bytes_of(path), before[f.name]) << "the workflow changed a factor texture";
        expect_shades_as(path, f.shading);
        const std::string stem = path.substr(0, path.size() - 4);
        for (const char* derived : {".tx", ".mip.tx", ".copy.exr", ".dwaa.exr"}) {
            EXPECT_FALSE(fs::exists(stem + derived)) << "the farm processed a factor texture: " << stem + derived;
        }
    }
    // The ordinary texture went through the farm's commands.
    for (const char* derived : {"albedo.tx", "albedo.mip.tx", "albedo.copy.exr", "albedo.dwaa.exr"}) {
        EXPECT_TRUE(fs::exists(dir + "/" + derived)) << derived << "\n" << run.log;
    }
}

// A farm that runs its commands over factor textures anyway: each tool succeeds, and what it
// wrote either shades exactly as the original or is refused, by NpfClosure and by one
// `npf info --check` over all the results of a file. Outcomes measured with OpenImageIO 2.4.7
// (docs/farms.md, "What the tools do to a factor texture").
TEST(FarmSafety, WhatTheToolsMakeOfAFactorTextureShadesTheSameOrIsRefused) {
    ASSERT_NO_FATAL_FAILURE(require_image_tools());
    enum class Outcome { Same, Refused, SameOrRefused };
    struct FarmCommand {
        std::string command;  // on m.exr, a copy of the factor texture, in a folder of its own
        std::string result;   // the file it writes
        Outcome outcome;
        std::string because;  // a phrase of the refusal
        // Changes pixels but keeps float as float: only npf:tables_checksum catches it, so files
        // written before it are not held to the outcome (docs/farms.md).
        bool needs_checksum = false;
    };
    const std::string tiff = "not an OpenEXR file but a TIFF";
    const std::string single_part = "holds only part \"D\" of an NPF factor texture";
    const std::string half = "stores half pixels, npf writes it as float";
    const std::string checksum = "do not match its npf:tables_checksum";
    const std::vector<FarmCommand> commands = {
        {"maketx m.exr", "m.tx", Outcome::Refused, tiff},
        {"maketx m.exr -o out.tx", "out.tx", Outcome::Refused, tiff},
        {"maketx m.exr -o out.exr", "out.exr", Outcome::Refused, single_part},
        {"maketx m.exr -o m.exr", "m.exr", Outcome::Refused, single_part},
        {"oiiotool m.exr -o out.exr", "out.exr", Outcome::Same, ""},
        {"oiiotool -a m.exr -o out.exr", "out.exr", Outcome::Same, ""},
        {"oiiotool m.exr -o m.exr", "m.exr", Outcome::Same, ""},
        {"oiiotool m.exr --compression dwaa -o out.exr", "out.exr", Outcome::Same, ""},
        {"oiiotool -a m.exr --compression dwaa -o out.exr", "out.exr", Outcome::Same, ""},
        {"oiiotool m.exr --tile 64 64 -o out.exr", "out.exr", Outcome::Same, ""},
        {"oiiotool m.exr -d half -o m.exr", "m.exr", Outcome::Refused, half},
        {"oiiotool m.exr --compression pxr24 -o out.exr", "out.exr", Outcome::Refused, checksum, true},
        // b44 rounds half channels only: the detail layer where there is one.
        {"oiiotool m.exr --compression b44 -o out.exr", "out.exr", Outcome::SameOrRefused, checksum, true},
        {"oiiotool m.exr --colorconvert linear sRGB -o out.exr", "out.exr", Outcome::Refused, single_part},
        {"oiiotool -a m.exr --colorconvert linear sRGB -o out.exr", "out.exr", Outcome::Refused, "", true},
        {"oiiotool -a m.exr --resize 200% -o out.exr", "out.exr", Outcome::Refused, "pixels, the attributes call for"},
        {"oiiotool m.exr -o out.tif", "out.tif", Outcome::Refused, tiff},
    };
    for (const FactorTexture& f : factor_textures()) {
        SCOPED_TRACE(f.name);
        // Every command in a folder of its own, in one shell.
        const std::string dir = npf::testing::temporary_folder("farm-commands");
        std::string script = "set -u\n";
        for (std::size_t i = 0; i < commands.size(); ++i) {
            const std::string sub = std::to_string(i);
            fs::create_directory(dir + "/" + sub);
            fs::copy_file(f.path, dir + "/" + sub + "/m.exr");
            const std::string& command = commands[i].command;
            script += "(cd " + sub + " && " + command + ") || echo \"FAILED: " + command + "\"\n";
        }
        const ShellRun run = shell(script, dir);
        ASSERT_FALSE(contains(run.log, "FAILED: ")) << "a tool failed (the measured tools all exit 0):\n" << run.log;

        std::vector<std::string> checked;  // the results `npf info --check` is held to, in order
        std::vector<std::string> refusals;  // "" where it must say ok
        for (std::size_t i = 0; i < commands.size(); ++i) {
            const FarmCommand& c = commands[i];
            SCOPED_TRACE(c.command);
            const std::string result = dir + "/" + std::to_string(i) + "/" + c.result;
            ASSERT_TRUE(fs::exists(result)) << run.log;
            if (c.needs_checksum && !f.sealed) {
                // Not protected (docs/farms.md): it may load with other values; it must not crash.
                try {
                    (void)shading_of(result);
                } catch (const npf::Error&) {
                }
                continue;
            }
            bool loads = true;
            try {
                (void)npf::read_npf_texture(result);
            } catch (const npf::Error&) {
                loads = false;
            }
            const bool same = c.outcome == Outcome::Same || (c.outcome == Outcome::SameOrRefused && loads);
            if (same) {
                expect_closures_shade_as(result, f.shading);
            } else {
                expect_closures_refuse(result, c.because);
            }
            checked.push_back(result);
            refusals.push_back(same ? "" : c.because);
        }
        std::vector<std::string> args = {"info", "--check"};
        args.insert(args.end(), checked.begin(), checked.end());
        const ToolRun check = npf::testing::run_tool(args);
        const std::vector<std::string> lines = npf::testing::lines_of(check.out);
        ASSERT_EQ(lines.size(), checked.size()) << describe(check);
        std::size_t refused = 0;
        for (std::size_t i = 0; i < checked.size(); ++i) {
            if (refusals[i].empty() && lines[i] == "ok: " + checked[i]) continue;
            ++refused;
            EXPECT_EQ(lines[i].rfind("error: " + checked[i] + ": ", 0), 0u) << lines[i];
            EXPECT_TRUE(contains(lines[i], refusals[i])) << lines[i] << "\nexpected: " << refusals[i];
        }
        EXPECT_EQ(check.status, refused > 0 ? 1 : 0) << describe(check);
    }
}

// Files written before npf:tables_checksum are sealed by writing them again with npf: the
// identity edit keeps every table bit for bit, and the result is protected like any new file.
TEST(FarmSafety, AnIdentityEditSealsAFileWrittenBeforeTheChecksum) {
    ASSERT_NO_FATAL_FAILURE(require_image_tools());
    const FactorTexture& old = factor_textures()[2];
    ASSERT_FALSE(old.sealed);
    const std::string dir = npf::testing::temporary_folder("farm-seal");
    const std::string sealed = dir + "/sealed.exr";
    const ToolRun edit = npf::testing::run_tool(
        {"edit", old.path, "-o", sealed, "--recipe", std::string(NPF_SOURCE_DIR) + "/configs/edits/identity.yaml"});
    ASSERT_EQ(edit.status, 0) << describe(edit);
    expect_shades_as(sealed, old.shading);
    ASSERT_EQ(shell("oiiotool sealed.exr --compression pxr24 -o pxr24.exr", dir).status, 0);
    expect_refused(dir + "/pxr24.exr", "do not match its npf:tables_checksum");
}

// npf:tables_checksum is what docs/format.md sec. 4 says: FNV-1a 64 over the parts' values in
// the documented order, computed here from the pixels as OpenImageIO reads them.
TEST(FarmSafety, TablesChecksumIsTheDocumentedFnv1a) {
    for (const FactorTexture& f : factor_textures()) {
        if (!f.sealed) continue;
        SCOPED_TRACE(f.name);
        std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(f.path);
        ASSERT_TRUE(in) << OIIO::geterror();
        std::map<std::string, std::pair<OIIO::ImageSpec, std::vector<float>>> parts;
        for (int i = 0; in->seek_subimage(i, 0); ++i) {
            const OIIO::ImageSpec& s = in->spec();
            std::vector<float> pixels(std::size_t(s.width) * std::size_t(s.height) * std::size_t(s.nchannels));
            ASSERT_TRUE(in->read_image(i, 0, 0, s.nchannels, OIIO::TypeFloat, pixels.data())) << in->geterror();
            parts[s.get_string_attribute("oiio:subimagename")] = {s, pixels};
        }
        std::uint64_t hash = 0xcbf29ce484222325ull;
        const auto add_channel = [&](const std::string& part, const std::string& channel) {
            const auto& [spec, pixels] = parts.at(part);
            const int c = spec.channelindex(channel);
            ASSERT_GE(c, 0) << part << " " << channel;
            for (std::size_t p = 0; p < pixels.size() / std::size_t(spec.nchannels); ++p) {
                std::uint32_t bits;
                std::memcpy(&bits, &pixels[p * std::size_t(spec.nchannels) + std::size_t(c)], 4);
                for (int b = 0; b < 4; ++b) hash = (hash ^ ((bits >> (8 * b)) & 0xffu)) * 0x100000001b3ull;
            }
        };
        // Channel families in their documented order: prefix and count per part.
        const auto add_family = [&](const std::string& part, const std::string& prefix, int count) {
            for (int k = 0; k < count; ++k) {
                char name[32];
                std::snprintf(name, sizeof name, "%s%03d", prefix.c_str(), k);
                add_channel(part, name);
            }
        };
        const OIIO::ImageSpec& d = parts.at("D").first;
        const int d_rank = d.get_int_attribute("npf:d_rank"), g_rank = d.get_int_attribute("npf:g_rank");
        const int channels = d.get_int_attribute("npf:channel_count"), r_rank = d.get_int_attribute("npf:detail_rank");
        add_family("D", "D.u", d_rank);
        add_family("G", "G.u", g_rank);
        add_family("F", "F.c", channels);
        for (const char* c : {"wavelength", "rho_d", "rho_s"}) add_channel("spectral", c);
        add_family("spectral", "D.v", d_rank);
        add_family("spectral", "G.v", g_rank);
        add_family("spectral", "R.v", r_rank);
        if (r_rank > 0) add_family("detail", "R.u", r_rank);
        char want[32];
        std::snprintf(want, sizeof want, "fnv1a64:%016llx", static_cast<unsigned long long>(hash));
        EXPECT_EQ(d.get_string_attribute("npf:tables_checksum"), want);
    }
}

// npf info --check: one line per file in order, text or JSON, exit 1 when any would not shade;
// every material source, and what maketx made of a factor texture.
TEST(FarmSafety, CheckReportsEachFileAndFailsIfAnyWouldNotShade) {
    ASSERT_NO_FATAL_FAILURE(require_image_tools());
    const std::string dir = npf::testing::temporary_folder("farm-check");
    const FactorTexture& f = factor_textures()[0];
    const std::string good = dir + "/good.exr";
    const std::string recipe = std::string(NPF_SOURCE_DIR) + "/configs/materials/red_plastic.yaml";
    fs::copy_file(f.path, good);
    ASSERT_EQ(shell("maketx good.exr", dir).status, 0);
    const std::string tx = dir + "/good.tx", missing = dir + "/missing.exr";

    const ToolRun ok = npf::testing::run_tool({"info", "--check", good, recipe});
    EXPECT_EQ(ok.status, 0) << describe(ok);
    EXPECT_EQ(ok.out, "ok: " + good + "\nok: " + recipe + "\n");
    EXPECT_EQ(ok.err, "");

    const ToolRun bad = npf::testing::run_tool({"info", "--check", good, tx, missing});
    EXPECT_EQ(bad.status, 1) << describe(bad);
    const std::vector<std::string> lines = npf::testing::lines_of(bad.out);
    ASSERT_EQ(lines.size(), 3u) << describe(bad);
    EXPECT_EQ(lines[0], "ok: " + good);
    EXPECT_EQ(lines[1].rfind("error: " + tx + ": not an OpenEXR file but a TIFF", 0), 0u) << lines[1];
    EXPECT_EQ(lines[2], "error: " + missing + ": cannot open: file not found");
    EXPECT_EQ(bad.err, "npf info: error: 2 of 3 files would not shade\n");

    const ToolRun json = npf::testing::run_tool({"info", "--check", "--json", good, tx});
    EXPECT_EQ(json.status, 1) << describe(json);
    EXPECT_EQ(json.out.rfind("[{\"file\": \"" + good + "\", \"ok\": true, \"error\": null},\n {\"file\": \"" + tx +
                                 "\", \"ok\": false, \"error\": \"" + tx + ": not an OpenEXR file but a TIFF",
                             0),
              0u)
        << json.out;
    EXPECT_EQ(json.out.substr(json.out.size() - 4), "\"}]\n") << json.out;

    // Without --check, and in every command that opens materials, the TIFF is named as well.
    const ToolRun info = npf::testing::run_tool({"info", tx});
    EXPECT_EQ(info.status, 1) << describe(info);
    EXPECT_TRUE(contains(info.err, "not an OpenEXR file but a TIFF")) << describe(info);
}

}  // namespace
