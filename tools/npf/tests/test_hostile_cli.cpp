// Hostile inputs through the commands (issue 33): unbounded text (class 4), outputs that alias each
// other or the inputs (class 7), memory out of proportion (class 8), errors that hid their cause
// (class 9) and loose validation (class 10). Each case failed on main 2821a5e (issue 33's note).
#include "error_of.h"
#include "npf_test_factors.h"
#include "raw_exr.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/converter/convert.h>
#include <npf/fit/spectral_compression.h>
#include <npf/materials/open_material.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/core/error.h>
#include <npf/shading/npf_texture_file.h>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using namespace npf::testing;  // run_tool, describe, contains, ...
using Fields = std::vector<SyntheticField>;

const std::string& folder() {
    static const std::string dir = npf::testing::temporary_folder("hostile-cli");
    return dir;
}

std::string file(const std::string& name) { return folder() + "/" + name; }


const std::string& small_texture() {
    static const std::string path = [] {
        npf::testing::TestFactorSpec kind;
        npf::NpfModel m = npf::compress_factors(npf::testing::make_test_factors(kind), {});
        m.metadata = {{"description", "hostile cli"}};
        npf::write_npf_texture(m, file("m.exr"));
        return file("m.exr");
    }();
    return path;
}

std::vector<unsigned char> bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void expect_fails_with(const std::vector<std::string>& args, const std::string& message) {
    const ToolRun run = run_tool(args);
    EXPECT_EQ(run.status, 1) << describe(run);
    EXPECT_TRUE(contains(run.out + run.err, message)) << describe(run);  // (info --check lists on stdout)
}

// ---- class 4: bounded text ------------------------------------------------------------------

TEST(HostileText, DirectionsFromAnEndlessStreamAreRefusedAtOnce) {
    // A sparse 3 GB file of zeros (no disk used) and one line of spaces with no end.
    const std::string zeros = file("zeros.txt"), spaces = file("spaces.txt");
    std::ofstream(zeros).close();
    ASSERT_EQ(::truncate(zeros.c_str(), off_t(3) << 30), 0);
    std::ofstream(spaces) << std::string(1 << 20, ' ');
    const auto start = std::chrono::steady_clock::now();
    expect_fails_with({"eval", small_texture(), "--dirs", zeros}, zeros + ":1: holds a NUL byte: not a text file");
    expect_fails_with({"eval", small_texture(), "--dirs", spaces}, spaces + ":1: a line longer than 4 KiB");
    // Standard input: the same, from a pipe.
    const ToolRun piped = run_tool({"eval", small_texture()}, {std::string(100000, '\0'), ""});
    EXPECT_EQ(piped.status, 1) << describe(piped);
    EXPECT_TRUE(contains(piped.err, "<stdin>:1: holds a NUL byte")) << describe(piped);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 30.0);
}

TEST(HostileText, RecipesAndSpectraAboveTheirCapsAreRefusedBeforeReading) {
    const std::string big = file("big.yaml");
    std::ofstream(big).close();
    ASSERT_EQ(::truncate(big.c_str(), off_t(2) << 20), 0);  // 2 MiB of zeros
    expect_fails_with({"info", big}, big + ": larger than the 1 MiB a recipe may hold");
    expect_fails_with({"edit", small_texture(), "-o", file("e.exr"), "--recipe", big}, "larger than the 1 MiB an edit recipe (.yaml) may hold");
    const std::string spd = file("zero.spd");
    std::ofstream(spd) << std::string("400 1\n") + std::string(10, '\0') + "\n";
    const std::string recipe = file("diffuse.yaml");
    std::ofstream(recipe) << "diffuse: " << spd << "\n";
    const ToolRun run = run_tool({"info", recipe});
    EXPECT_EQ(run.status, 1) << describe(run);
    EXPECT_TRUE(contains(run.err, spd + ":2: holds a NUL byte")) << describe(run);
}

// ---- class 7: outputs that alias each other or the inputs ------------------------------------

TEST(HostileOutputs, AnOutputThatIsAnotherOutputOrAnInputIsRefusedBeforeAnyWork) {
    const std::string m = small_texture();
    const std::vector<unsigned char> before = bytes_of(m);
    expect_fails_with({"render", m, "-o", file("x"), "--png", file("x"), "--size", "8", "--spp", "1"},
                      file("x") + ": is named twice (-o and --png): one output would replace the other");
    expect_fails_with({"render", m, "-o", m, "--size", "8", "--spp", "1"}, "is named twice (the material and -o)");
    // Another name for the input: a hard link, a symbolic link, another spelling.
    ASSERT_EQ(::link(m.c_str(), file("hard.exr").c_str()), 0);
    fs::create_symlink(m, file("soft.exr"));
    for (const std::string& alias : {file("hard.exr"), file("soft.exr"), folder() + "/./m.exr"}) {
        expect_fails_with({"convert", m, "-o", alias, "--preset", "preview"}, ": the output would replace an input");
        expect_fails_with({"edit", m, "-o", alias, "--limit-albedo", "1"}, ": the output would replace an input");
        expect_fails_with({"render", alias, "-o", m, "--size", "8", "--spp", "1"}, ": the output would replace an input");
    }
    expect_fails_with({"compare", m, m, "--heatmap", m}, "(REF and --heatmap): the output would replace an input");
    // A file an edit recipe names (a spectrum) is an input too.
    const std::string spd = file("tint.spd"), recipe = file("tint.yaml");
    std::ofstream(spd) << "400 0.5\n700 0.5\n";
    std::ofstream(recipe) << "steps:\n  - diffuse: {spectrum: " << spd << "}\n";
    expect_fails_with({"edit", m, "-o", spd, "--recipe", recipe}, "the output would replace an input");
    EXPECT_EQ(bytes_of(m), before);
    EXPECT_EQ(bytes_of(spd), std::vector<unsigned char>({'4', '0', '0', ' ', '0', '.', '5', '\n', '7', '0', '0', ' ', '0', '.', '5', '\n'}));
    // Devices are written through, never replaced: /dev/null twice is fine.
    const ToolRun devnull = run_tool({"render", m, "-o", "/dev/null", "--png", "/dev/null", "--size", "8", "--spp", "1", "--quiet"});
    EXPECT_EQ(devnull.status, 0) << describe(devnull);
}

// ---- class 8: memory in proportion ----------------------------------------------------------

TEST(HostileSizes, AFactorTextureMayNotExpandFarBeyondItsSize) {
    // Constant tables at 512 x 512 cells, rank 16: 33 MB of floats from a file of ~50 kB.
    npf::NpfModel m;
    m.channels = npf::Channels::rgb();
    m.d_theta = m.g_theta = 512;
    m.d_phi = m.g_phi = 512;
    m.f_theta = 8;
    m.rho_d.assign(3, 0.01f);
    m.rho_s.assign(3, 0.01f);
    m.F.assign(3 * 8, 0.5f);
    for (npf::SpectralBasis* b : {&m.D, &m.G}) {
        b->rank = 3;
        b->cells = 512 * 512;
        b->basis.assign(b->cells * 3, 0.001f);
        b->weights.assign(9, 0.001f);
        b->singular_values = {1.0, 1.0, 1.0};
    }
    m.detail_grid = npf::DetailGrid{128, 64, 128};
    m.detail.rank = 3;
    m.detail.cells = m.detail_grid.cells();
    m.detail.basis.assign(m.detail.cells * 3, 0.f);
    m.detail.weights.assign(9, 0.f);
    m.detail.singular_values = {0.0, 0.0, 0.0};
    const std::string path = file("expands.exr");
    npf::write_npf_texture(m, path);
    ASSERT_LT(fs::file_size(path), 2u << 20);
    const std::string e = error_of([&] { npf::read_npf_texture(path); });
    EXPECT_TRUE(contains(e, path + ": its tables would take")) << e;
    EXPECT_TRUE(contains(e, "a factor texture may expand to 16 times its size plus 16 MiB: refused")) << e;
    expect_fails_with({"info", "--check", path}, "its tables would take");
}

TEST(HostileSizes, ARecipesGridMayNotAskForMoreThanTheReaderTakes) {
    // Every axis at its 4096 maximum: 10^17 bytes of vndf; an allocation failure before.
    const std::string recipe = file("griddy.yaml");
    std::ofstream(recipe) << "lobes:\n  - {distribution: ggx, alpha: 0.3}\ngrid: {phi: 4096, theta: 4096, data: 4096, vndf: 4096}\n"
                             "anisotropy: anisotropic\n";
    expect_fails_with({"synth", "--recipe", recipe, "-o", file("griddy.bsdf")},
                      "griddy.bsdf: the grid asks for a field 'vndf' of 1073741824 MiB; an RGL field may hold at most 1024 MiB");
    EXPECT_FALSE(fs::exists(file("griddy.bsdf")));
}

// ---- class 9: errors that hid their cause ---------------------------------------------------

TEST(HostileCauses, AConversionStagesErrorNamesTheMaterial) {
    // A stage's own check ("detail layer: ...") used to be the whole message, naming no file.
    npf::testing::SyntheticRglSpec spec;
    spec.theta_count = 3;
    const std::string source = npf::testing::write_synthetic_rgl(spec, file("stage.bsdf"));
    npf::ConvertSettings s = npf::preset_settings(npf::ConvertPreset::Preview, true);
    s.predict_psnr = false;
    s.detail.samples_per_cell = 0;
    const std::string e = error_of([&] { npf::convert_material(*npf::open_material(source), file("stage.exr"), s); });
    EXPECT_EQ(e, source + ": detail layer: samples per cell must be 1..16");
    EXPECT_FALSE(fs::exists(file("stage.exr")));
}

TEST(HostileCauses, TheTexturePathReadsAFactorTextureAsOpenExrWhateverItsName) {
    // OpenImageIO picks a reader by the extension, and its null reader takes parameters from the
    // name: this file was read as a 20000 x 20000 procedural image (refused as 6.4 GB, by luck).
    const std::string odd = file("q.null?RES=20000x20000");
    fs::copy_file(small_texture(), odd);
    const ToolRun run = run_tool({"info", "--check", odd});
    EXPECT_EQ(run.status, 0) << describe(run);
}

// ---- class 10: loose validation made strict -------------------------------------------------

std::string rgl_with(const std::string& name, const std::function<void(Fields&)>& edit) {
    npf::testing::SyntheticRglSpec s;
    s.theta_count = 3;
    s.ndf_size = 8;
    s.vndf_size = 6;
    s.data_size = 4;
    Fields fields = npf::testing::synthetic_rgl_fields(s);
    edit(fields);
    const std::string path = file(name);
    npf::testing::to_writer(fields).write(path);
    return path;
}

npf::testing::SyntheticField u8_field(const std::string& name, const std::vector<std::uint8_t>& bytes) {
    npf::testing::SyntheticField f;
    f.name = name;
    f.dtype = npf::DType::U8;
    f.shape = {bytes.size()};
    f.bytes = bytes;
    return f;
}

TEST(HostileValidation, RglFieldsOutsideTheirMeaningAreRefused) {
    const auto expect_refused = [](const std::string& path, const std::string& message) {
        const std::string e = error_of([&] { npf::RglBrdf::load(path); });
        EXPECT_TRUE(contains(e, path + ": " + message)) << e;
    };
    expect_refused(rgl_with("jacobian7.bsdf", [](Fields& f) { npf::testing::find_field(f, "jacobian")->bytes = {7}; }),
                   "field 'jacobian' is 7; it must be 0 or 1");
    expect_refused(rgl_with("both.bsdf",
                            [](Fields& f) {
                                npf::testing::SyntheticField spectra = *npf::testing::find_field(f, "rgb");
                                spectra.name = "spectra";
                                f.push_back(spectra);
                                npf::testing::SyntheticField wl;
                                wl.name = "wavelengths";
                                wl.shape = {3};
                                wl.set_floats({400.f, 500.f, 600.f});
                                f.push_back(wl);
                            }),
                   "holds both 'rgb' and 'spectra'");
    expect_refused(rgl_with("valid3.bsdf", [](Fields& f) { f.push_back(u8_field("valid", {255, 255, 255})); }),
                   "field 'valid' holds 3 bytes; one bit per data node");
    expect_refused(rgl_with("version.bsdf",
                            [](Fields& f) {
                                npf::testing::SyntheticField v;
                                v.name = "version";
                                v.dtype = npf::DType::U32;
                                v.shape = {3};
                                v.bytes = {9, 0, 0, 0, 9, 0, 0, 0, 9, 0, 0, 0};
                                f.push_back(v);
                            }),
                   "field 'version' is 9.9.9; this reader knows the measurement layout 1.0 only");
    // The shared files say 1.0 and carry a mask of the right size: they still load.
    const std::string ilm = npf::testing::shared_data_file("rgl/ilm_l3_37_metallic_rgb.bsdf");
    if (!ilm.empty()) {
        EXPECT_NO_THROW(npf::RglBrdf::load(ilm));
    }
}

TEST(HostileValidation, ControlCharactersInANameCannotSplitAMessage) {
    const std::string odd = file("two\nlines\x1b[2J.exr");
    std::ofstream(odd) << "not a material";
    const ToolRun run = run_tool({"info", odd});
    EXPECT_EQ(run.status, 1) << describe(run);
    EXPECT_EQ(npf::testing::lines_of(run.err).size(), 1u) << describe(run);
    EXPECT_TRUE(contains(run.err, "two\\nlines\\x1b[2J.exr: ")) << describe(run);
}

}  // namespace
