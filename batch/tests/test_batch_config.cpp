// The batch library without the tool: configuration parsing and its errors (file:line and key),
// the settings -> ConvertSettings mapping, content hashes, shards, summaries and their merge.
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/batch/config.h>
#include <npf/batch/content_hash.h>
#include <npf/batch/runner.h>
#include <npf/batch/summary.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>

namespace {

using npf::testing::contains;
namespace batch = npf::batch;

const std::string& folder() {
    static const std::string dir = npf::testing::temporary_folder("batch-config");
    return dir;
}

std::string inputs_dir() {
    std::filesystem::create_directories(folder() + "/in");
    for (const char* name : {"a.bsdf", "b.bsdf", "c.binary"}) npf::testing::write_text(folder() + "/in/" + name, "x");
    return folder() + "/in";
}

batch::BatchConfig parse(const std::string& yaml) { return batch::parse_batch_config(yaml, "cfg.yaml", inputs_dir()); }

// The message of the npf::Error that parsing `yaml` throws ("" when it does not throw).
std::string error_of(const std::string& yaml) {
    try {
        parse(yaml);
    } catch (const npf::Error& e) {
        return e.what();
    }
    return "";
}

TEST(BatchConfig, ReadsInputsDefaultsAndOverrides) {
    const batch::BatchConfig c = parse("output_dir: out\n"
                                       "inputs: ['*.bsdf', c.binary, missing.bsdf]\n"
                                       "defaults: {preset: preview, threads: 2, grid: [16, 1, 16, 32]}\n"
                                       "materials:\n"
                                       "  b: {preset: production, edit: recipe.yaml, render: {size: 32, spp: 4}}\n"
                                       "  c: {skip: true}\n");
    EXPECT_EQ(c.output_dir, inputs_dir() + "/out");
    ASSERT_EQ(c.materials.size(), 3u);  // a, b, missing (literal paths are kept; they fail when run)
    EXPECT_EQ(c.materials[0].name, "a");
    EXPECT_EQ(c.materials[1].name, "b");
    EXPECT_EQ(c.materials[2].name, "missing");
    EXPECT_EQ(c.skipped_by_config, std::vector<std::string>{"c"});
    EXPECT_EQ(c.materials[0].input, inputs_dir() + "/a.bsdf");
    EXPECT_EQ(c.materials[0].output, inputs_dir() + "/out/a.exr");
    EXPECT_EQ(c.materials[0].settings.at("preset").value, "preview");
    EXPECT_EQ(c.materials[0].settings.at("grid").value, "16,1,16,32");
    EXPECT_EQ(c.materials[1].settings.at("preset").value, "production");
    EXPECT_EQ(c.materials[1].settings.at("preset").origin, "cfg.yaml:5");
    EXPECT_EQ(c.materials[1].settings.at("edit").value, inputs_dir() + "/recipe.yaml");
    EXPECT_EQ(c.materials[1].settings.at("render.size").value, "32");
    const batch::RenderCheck r = batch::resolve_render_check(c.materials[1].settings);
    EXPECT_TRUE(r.enabled);
    EXPECT_EQ(r.size, 32u);
    EXPECT_EQ(r.spp, 4u);
    EXPECT_FALSE(batch::resolve_render_check(c.materials[0].settings).enabled);
    EXPECT_TRUE(c.warnings.empty());
}

// The validation renders' lightings: render.env (names as they are, maps from the
// configuration's folder), else the conversion's `light` set, else the built-in set.
TEST(BatchConfig, RenderLightingsComeFromEnvThenLightThenTheBuiltInSet) {
    npf::testing::write_text(inputs_dir() + "/dusk map.exr", "x");  // checked for existence only here
    const batch::BatchConfig c = parse("output_dir: out\ninputs: ['*.bsdf']\ndefaults: {render: true}\n"
                                       "materials:\n"
                                       "  a: {render: {env: [directional, dusk map.exr]}}\n"
                                       "  b: {light: 'key-rim,studio'}\n");
    ASSERT_EQ(c.materials.size(), 2u);
    EXPECT_EQ(batch::resolve_render_check(c.materials[0].settings).lightings,
              (std::vector<std::string>{"directional", inputs_dir() + "/dusk map.exr"}));
    EXPECT_EQ(batch::resolve_render_check(c.materials[1].settings).lightings, (std::vector<std::string>{"key-rim", "studio"}));
    const batch::BatchConfig d = parse("output_dir: out\ninputs: a.bsdf\ndefaults: {render: {env: ' studio , key-rim'}}\n");
    EXPECT_EQ(batch::resolve_render_check(d.materials[0].settings).lightings, (std::vector<std::string>{"studio", "key-rim"}));
    const batch::BatchConfig e = parse("output_dir: out\ninputs: a.bsdf\ndefaults: {render: true}\n");
    EXPECT_EQ(batch::resolve_render_check(e.materials[0].settings).lightings,
              (std::vector<std::string>{"studio", "key-rim", "directional"}));
    const std::string missing = error_of("output_dir: out\ninputs: a.bsdf\ndefaults:\n  render: {env: [studio, nowhere.exr]}\n");
    EXPECT_TRUE(contains(missing, "cfg.yaml:4: key 'defaults.render.env': ")) << missing;
    EXPECT_TRUE(contains(missing, "nowhere.exr")) << missing;
    EXPECT_TRUE(contains(error_of("output_dir: out\ninputs: a.bsdf\ndefaults:\n  render: {env: 'studio,,key-rim'}\n"),
                         "an empty lighting in the list"));
    EXPECT_TRUE(contains(error_of("output_dir: out\ninputs: a.bsdf\ndefaults:\n  render: {env: [studio, studio]}\n"),
                         "given twice"));
}

TEST(BatchConfig, SettingsResolveAsTheConvertFlagsDo) {
    const batch::BatchConfig c = parse("output_dir: out\ninputs: a.bsdf\n"
                                       "defaults: {preset: preview, grid: '20,1,18,36', g_grid: [18, 1], pca: [0.9, 0.8],\n"
                                       "           importance: 1, g_prior: smith, plain: true, error_pairs: 0, threads: 3,\n"
                                       "           wavelengths: '400:700:4', iterations: 7, tolerance: 0.01}\n");
    const npf::ConvertSettings s = batch::resolve_convert_settings(c.materials[0].settings, true);
    EXPECT_EQ(s.preset, npf::ConvertPreset::Preview);
    EXPECT_EQ(s.fit.grid.theta_h, 20);
    EXPECT_EQ(s.fit.grid.phi_d, 36);
    EXPECT_EQ(s.fit.g_theta, 18);
    EXPECT_DOUBLE_EQ(s.compression.d_ratio, 0.9);
    EXPECT_DOUBLE_EQ(s.compression.g_ratio, 0.8);
    EXPECT_TRUE(s.compress_rgb);
    EXPECT_DOUBLE_EQ(s.fit.importance_power_view, 1.0);
    EXPECT_DOUBLE_EQ(s.fit.importance_power_light, 1.0);
    EXPECT_TRUE(s.fit.smith_start && s.fit.bound_g);
    EXPECT_EQ(s.fit.acceleration, npf::AwlsOptions::Acceleration::None);
    EXPECT_EQ(s.error_pairs, 0);
    EXPECT_EQ(s.fit.threads, 3);
    EXPECT_EQ(s.wavelengths, "400:700:4");
    EXPECT_EQ(s.fit.max_iterations, 7);
    // The preset alone, for an anisotropic source, is the preset's anisotropic grid.
    const batch::BatchConfig p = parse("output_dir: out\ninputs: a.bsdf\ndefaults: {preset: preview}\n");
    const npf::ConvertSettings a = batch::resolve_convert_settings(p.materials[0].settings, false);
    const npf::ConvertSettings want = npf::preset_settings(npf::ConvertPreset::Preview, false);
    EXPECT_EQ(a.fit.grid.phi_h, want.fit.grid.phi_h);
    EXPECT_EQ(a.fit.phi_d_samples, want.fit.phi_d_samples);
    // Threads, edits and renders stay out of the canonical text; the rest is in name order.
    EXPECT_EQ(batch::canonical_settings(c.materials[0].settings),
              "error_pairs=0\ng_grid=18,1\ng_prior=smith\ngrid=20,1,18,36\nimportance=1\niterations=7\npca=0.9,0.8\n"
              "plain=true\npreset=preview\ntolerance=0.01\nwavelengths=400:700:4\n");
}

// "importance: [view, light]" splits w_I, and only then does the hash text change.
TEST(BatchConfig, SplitImportancePowers) {
    const batch::BatchConfig c = parse("output_dir: out\ninputs: a.bsdf\ndefaults: {importance: [1, 2]}\n");
    const npf::ConvertSettings s = batch::resolve_convert_settings(c.materials[0].settings, true);
    EXPECT_DOUBLE_EQ(s.fit.importance_power_view, 1.0);
    EXPECT_DOUBLE_EQ(s.fit.importance_power_light, 2.0);
}

TEST(BatchConfig, ErrorsNameTheLineAndTheKey) {
    struct Case {
        std::string yaml, expected;
    };
    const Case cases[] = {
        {"output_dir: out\ninputs: a.bsdf\ndefaults:\n  preset: fast\n", "cfg.yaml:4: key 'defaults.preset': 'fast' is not one of preview, production, fine, paper"},
        {"output_dir: out\ninputs: a.bsdf\ndefaults:\n  presett: preview\n", "cfg.yaml:4: key 'defaults.presett': unknown key"},
        {"output_dir: out\ninputs: a.bsdf\nbogus: 1\n", "cfg.yaml:3: key 'bogus': unknown key"},
        {"inputs: a.bsdf\n", "cfg.yaml: key 'output_dir' is required"},
        {"output_dir: out\n", "key 'inputs' is required"},
        {"output_dir: out\ninputs: a.bsdf\ndefaults: {threads: 0}\n", "cfg.yaml:3: key 'defaults.threads': needs a whole number in [1, 1024]"},
        {"output_dir: out\ninputs: a.bsdf\ndefaults:\n  grid: [1, 2]\n", "cfg.yaml:4: key 'defaults.grid': expects 4 values"},
        {"output_dir: out\ninputs: a.bsdf\ndefaults:\n  pca: [0.9, 1.5]\n", "cfg.yaml:4: key 'defaults.pca': ratios must lie in (0, 1]"},
        {"output_dir: out\ninputs: a.bsdf\ndefaults:\n  render: {size: 64, colour: red}\n", "cfg.yaml:4: key 'defaults.render.colour': unknown key"},
        {"output_dir: out\ninputs: a.bsdf\ndefaults:\n  importance: [1, 2, 3]\n", "cfg.yaml:4: key 'defaults.importance': expects 2 values"},
        {"output_dir: out\ninputs: a.bsdf\ndefaults:\n  importance: [1, x]\n", "cfg.yaml:4: key 'defaults.importance':"},
        {"output_dir: out\ninputs: a.bsdf\ndefaults:\n  render: maybe\n", "cfg.yaml:4: key 'defaults.render': expects true or false"},
        {"output_dir: out\ninputs: a.bsdf\nmaterials:\n  zzz: {preset: paper}\n", "cfg.yaml:4: key 'materials.zzz': no input is named 'zzz'"},
        {"output_dir: out\ninputs: a.bsdf\nmaterials:\n  a:\n    input: b.bsdf\n", "cfg.yaml:5: key 'materials.a.input': 'a' is already an input"},
        {"output_dir: out\ninputs: [a.bsdf, other/a.bsdf]\n", "two inputs are named 'a'"},
        {"output_dir: out\ninputs: a.bsdf\nnaming: out.exr\n", "cfg.yaml:3: key 'naming': must contain {name}"},
        {"output_dir: out\ninputs: a.bsdf\nnaming: '{name}.png'\n", "key 'naming': must end in .exr"},
        {"output_dir: out\ninputs: a.bsdf\nversion: 2\n", "cfg.yaml:3: key 'version': only version 1 is known"},
        {"output_dir: out\ninputs: [a.bsdf\n", "cfg.yaml:3: not valid YAML:"},
        {"output_dir: out\ninputs: a.bsdf\ndefaults:\n  preset: preview\n  preset: paper\n", "cfg.yaml:5: key 'preset': given twice"},
        {"output_dir: out\ninputs: a.bsdf\ndefaults:\n  wavelengths: 700:400:x\n", "cfg.yaml:4: key 'defaults.wavelengths':"},
        {"output_dir: out\ninputs: a.bsdf\ndefaults:\n  edit:\n", "cfg.yaml:4: key 'edit': has no value"},
        {"- a\n- b\n", "cfg.yaml: expected a mapping"},
        {"output_dir: out\ninputs: []\n", "cfg.yaml:2: key 'inputs': expected a path or glob"},
    };
    for (const Case& c : cases) {
        const std::string e = error_of(c.yaml);
        EXPECT_TRUE(contains(e, c.expected)) << "yaml:\n" << c.yaml << "\nerror: " << e << "\nexpected: " << c.expected;
    }
}

TEST(BatchConfig, GlobsThatMatchNothingWarn) {
    const batch::BatchConfig c = parse("output_dir: out\ninputs: ['*.nothing', a.bsdf]\n");
    ASSERT_EQ(c.warnings.size(), 1u);
    EXPECT_TRUE(contains(c.warnings[0], "cfg.yaml:2")) << c.warnings[0];
    EXPECT_TRUE(contains(c.warnings[0], "matches no file")) << c.warnings[0];
    EXPECT_EQ(c.materials.size(), 1u);
}

TEST(BatchConfig, LoadsFromAFileWithPathsFromItsFolder) {
    const std::string dir = npf::testing::temporary_folder("batch-config-file");
    npf::testing::write_text(dir + "/m.bsdf", "x");
    npf::testing::write_text(dir + "/batch.yaml", "output_dir: converted\ninputs: m.bsdf\n");
    const batch::BatchConfig c = batch::load_batch_config(dir + "/batch.yaml");
    EXPECT_EQ(c.output_dir, std::filesystem::path(dir + "/converted").lexically_normal().string());
    ASSERT_EQ(c.materials.size(), 1u);
    EXPECT_EQ(c.materials[0].input, std::filesystem::path(dir + "/m.bsdf").lexically_normal().string());
    EXPECT_THROW(batch::load_batch_config(dir + "/none.yaml"), npf::Error);
    EXPECT_THROW(batch::load_batch_config(dir), npf::Error);
}

// An input whose name holds "{name}" is named once, not expanded again (fuzzing: the old loop
// replaced the {name} it had just put in, for ever), and its output is still known as an output.
TEST(BatchConfig, AnInputNamedWithTheNamingPlaceholderIsNamedOnce) {
    const std::string dir = npf::testing::temporary_folder("batch-config-placeholder");
    npf::testing::write_text(dir + "/a{name}b.bsdf", "x");
    npf::testing::write_text(dir + "/batch.yaml", "output_dir: out\nnaming: '{name}_{name}.exr'\ninputs: '*.bsdf'\n");
    const batch::BatchConfig c = batch::load_batch_config(dir + "/batch.yaml");
    ASSERT_EQ(c.materials.size(), 1u);
    EXPECT_EQ(c.materials[0].name, "a{name}b");
    EXPECT_EQ(std::filesystem::path(c.materials[0].output).filename().string(), "a{name}b_a{name}b.exr");
    EXPECT_EQ(batch::batch_file_kind(c, c.materials[0].output), "an output of the batch (naming '{name}_{name}.exr')");
}

// The batch's own files are never inputs (docs/batch.md): a glob over the output folder leaves
// out the outputs (any name that fits `naming`), the work folder with its locks, the renders,
// the summaries (by name, and any summary by its contents) and the configuration itself, also
// when the folder is reached through a symbolic link. A literal path to one is an error.
TEST(BatchConfig, TheBatchsOwnFilesAreNeverInputs) {
    namespace fs = std::filesystem;
    const std::string dir = npf::testing::temporary_folder("batch-own-files");
    const std::string lib = dir + "/lib";
    fs::create_directories(lib + "/.npf-batch/shard-0-of-1");
    fs::create_directories(lib + "/renders");
    fs::create_directories(dir + "/sums");
    for (const char* f : {"a.bsdf", "b.binary", "a_npf.exr", "old_npf.exr", "batch-summary.json", "batch-summary.md",
                          "batch-summary.shard-1-of-2.json", ".npf-batch/shard-0-of-1.lock", ".npf-batch/shard-0-of-1/a_npf.exr",
                          "renders/a_npf.npf.exr", "renders/a_npf.reference.exr"})
        npf::testing::write_text(lib + "/" + f, "x");
    // Summaries written elsewhere (--summary, merges) are known by their first bytes.
    npf::testing::write_text(dir + "/sums/merged.json", "{\n  \"npf_batch_summary\": 1,\n");
    npf::testing::write_text(dir + "/sums/merged.md", "# npf batch summary\n\n");
    npf::testing::write_text(dir + "/sums/c.bsdf", "x");
    fs::create_directory_symlink(lib, dir + "/link");
    const std::string cfg = lib + "/batch.yaml";
    npf::testing::write_text(cfg, "output_dir: .\nnaming: '{name}_npf.exr'\n"
                                  "inputs: ['*', '.npf-batch/*', '.npf-batch/*/*', 'renders/*', '../sums/*', '../link/*.yaml']\n");
    const batch::BatchConfig c = batch::load_batch_config(cfg);
    std::vector<std::string> names;
    for (const batch::MaterialJob& m : c.materials) names.push_back(m.name);
    EXPECT_EQ(names, (std::vector<std::string>{"a", "b", "c"}));
    EXPECT_EQ(c.excluded.size(), 13u);
    // The globs that matched only the batch's own files say so.
    ASSERT_EQ(c.warnings.size(), 4u);
    for (const std::string& w : c.warnings) EXPECT_TRUE(contains(w, "matches only files the batch writes")) << w;
    EXPECT_EQ(batch::batch_file_kind(c, lib + "/zzz_npf.exr"), "an output of the batch (naming '{name}_npf.exr')");
    EXPECT_EQ(batch::batch_file_kind(c, dir + "/link/.npf-batch/x"), "in the batch's work folder (.npf-batch)");
    EXPECT_EQ(batch::batch_file_kind(c, lib + "/a.bsdf"), "");

    // Literal paths to the batch's files are refused, naming the key.
    const auto error_in = [&](const std::string& yaml) {
        try {
            batch::parse_batch_config(yaml, "cfg.yaml", dir);
        } catch (const npf::Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_TRUE(contains(error_in("output_dir: lib\ninputs: [lib/a.bsdf, lib/x.exr]\n"),
                         "cfg.yaml:2: key 'inputs': '" + lib + "/x.exr' is an output of the batch"));
    EXPECT_TRUE(contains(error_in("output_dir: lib\ninputs: lib/a.bsdf\nmaterials:\n  s: {input: lib/batch-summary.md}\n"),
                         "key 'materials.s.input': '" + lib + "/batch-summary.md' is the batch's summary"));
    EXPECT_TRUE(contains(error_in("output_dir: out\ninputs: [lib/a.bsdf, sums/merged.json]\n"), "is an npf batch summary"));
}

// memory_limit and time_limit: settings per material (and flags), checked where they are
// written, and outside the content hash (they decide whether a conversion ends, not its bytes).
TEST(BatchConfig, LimitsAreSettingsOutsideTheHash) {
    const batch::BatchConfig c = parse("output_dir: out\ninputs: ['*.bsdf']\n"
                                       "defaults: {preset: preview, memory_limit: 2 GiB, time_limit: 30 min}\n"
                                       "materials:\n  b: {memory_limit: 512M, time_limit: none}\n");
    ASSERT_EQ(c.materials.size(), 2u);
    const batch::MaterialLimits a = batch::resolve_limits(c.materials[0].settings), b = batch::resolve_limits(c.materials[1].settings);
    EXPECT_EQ(a.memory_bytes, std::uint64_t(2) << 30);
    EXPECT_DOUBLE_EQ(a.seconds, 1800.0);
    EXPECT_EQ(b.memory_bytes, std::uint64_t(512) << 20);
    EXPECT_EQ(b.seconds, 0.0);
    const batch::MaterialLimits d = batch::resolve_limits({});
    EXPECT_EQ(d.memory_bytes, batch::kDefaultMemoryLimit);
    EXPECT_EQ(d.seconds, batch::kDefaultTimeLimit);
    EXPECT_EQ(batch::canonical_settings(c.materials[0].settings), "preset=preview\n");
    const batch::BatchConfig plain = parse("output_dir: out\ninputs: ['*.bsdf']\ndefaults: {preset: preview}\n");
    EXPECT_EQ(batch::material_hash(c.materials[0], true), batch::material_hash(plain.materials[0], true));

    EXPECT_EQ(batch::parse_memory_limit("8 GiB", "x"), std::uint64_t(8) << 30);
    EXPECT_EQ(batch::parse_memory_limit("1.5g", "x"), std::uint64_t(3) << 29);
    EXPECT_EQ(batch::parse_memory_limit("none", "x"), 0u);
    EXPECT_DOUBLE_EQ(batch::parse_time_limit("6 h", "x"), 21600.0);
    EXPECT_DOUBLE_EQ(batch::parse_time_limit("2.5", "x"), 2.5);
    EXPECT_EQ(batch::describe_memory(std::uint64_t(8) << 30), "8 GiB");
    EXPECT_EQ(batch::describe_memory(std::uint64_t(3) << 29), "1.5 GiB");
    EXPECT_EQ(batch::describe_memory(std::uint64_t(512) << 20), "512 MiB");
    EXPECT_EQ(batch::describe_seconds(3600), "3600 s");
    struct Case {
        std::string yaml, expected;
    };
    const Case cases[] = {
        {"defaults: {memory_limit: 8}", "cfg.yaml:3: key 'defaults.memory_limit': needs a unit"},
        {"defaults: {memory_limit: 1 MiB}", "key 'defaults.memory_limit': must be at least 64 MiB"},
        {"defaults: {memory_limit: lots}", "key 'defaults.memory_limit': expects a size"},
        {"defaults: {time_limit: 0}", "key 'defaults.time_limit': must be above 0"},
        {"defaults: {time_limit: 2 days}", "key 'defaults.time_limit': unit 'days' is not one of s, min, h"},
        {"materials:\n  a: {time_limit: -1}", "cfg.yaml:4: key 'materials.a.time_limit': expects seconds"},
    };
    for (const Case& k : cases) {
        const std::string e = error_of("output_dir: out\ninputs: ['*.bsdf']\n" + k.yaml + "\n");
        EXPECT_TRUE(contains(e, k.expected)) << k.yaml << "\nerror: " << e << "\nexpected: " << k.expected;
    }
}

TEST(BatchConfig, TheShippedExampleIsValid) {
    const batch::BatchConfig c = batch::load_batch_config(std::string(NPF_SOURCE_DIR) + "/configs/batch/example.yaml");
    EXPECT_GE(c.materials.size(), 6u);
    EXPECT_TRUE(c.warnings.empty());
}

TEST(BatchHash, Sha256KnownVectors) {
    EXPECT_EQ(batch::sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(batch::sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(batch::sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    std::string million(1000000, 'a');
    EXPECT_EQ(batch::sha256_hex(million), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
    // Fed in pieces of awkward sizes: the same digest.
    batch::Sha256 h;
    for (std::size_t at = 0; at < million.size();) {
        const std::size_t n = std::min<std::size_t>(million.size() - at, 1 + at % 97);
        h.update(million.data() + at, n);
        at += n;
    }
    EXPECT_EQ(h.hex(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
    const std::string file = folder() + "/hash.txt";
    npf::testing::write_text(file, "abc");
    EXPECT_EQ(batch::sha256_file(file), batch::sha256_hex("abc"));
    EXPECT_THROW(batch::sha256_file(folder() + "/none"), npf::Error);
}

TEST(BatchHash, ChangesWithInputSettingsAndEdit) {
    const std::string dir = npf::testing::temporary_folder("batch-hash");
    npf::testing::write_text(dir + "/m.bsdf", "one");
    npf::testing::write_text(dir + "/recipe.yaml", "steps:\n  - rotate: 30\n");
    const auto job = [&](const std::string& defaults) {
        return batch::parse_batch_config("output_dir: out\ninputs: m.bsdf\ndefaults: " + defaults + "\n", "h.yaml", dir).materials.at(0);
    };
    const std::string base = batch::material_hash(job("{preset: preview}"), true);
    EXPECT_EQ(base.size(), 64u);
    EXPECT_EQ(batch::material_hash(job("{preset: preview}"), true), base);
    EXPECT_EQ(batch::material_hash(job("{preset: preview, threads: 7}"), true), base);     // threads: not hashed
    EXPECT_EQ(batch::material_hash(job("{preset: preview, render: true}"), true), base);   // renders: their own hash
    EXPECT_EQ(batch::material_hash(job("{preset: preview, grid: [45, 1, 45, 90]}"), true), base);  // the preset's own value
    EXPECT_NE(batch::material_hash(job("{preset: preview}"), false), base);  // another resolved grid
    EXPECT_NE(batch::material_hash(job("{preset: production}"), true), base);
    EXPECT_NE(batch::material_hash(job("{preset: preview, error_pairs: 100}"), true), base);
    const std::string edited = batch::material_hash(job("{preset: preview, edit: recipe.yaml}"), true);
    EXPECT_NE(edited, base);
    npf::testing::write_text(dir + "/recipe.yaml", "steps:\n  - rotate: 31\n");
    EXPECT_NE(batch::material_hash(job("{preset: preview, edit: recipe.yaml}"), true), edited);
    npf::testing::write_text(dir + "/m.bsdf", "two");
    EXPECT_NE(batch::material_hash(job("{preset: preview}"), true), base);
}

TEST(BatchShard, MembersAreDisjointAndComplete) {
    EXPECT_EQ(batch::parse_shard("1/3").index, 1);
    EXPECT_EQ(batch::parse_shard("1/3").count, 3);
    for (const char* bad : {"3/3", "1", "-1/2", "a/b", "0/0", "1/2/3", ""}) EXPECT_THROW(batch::parse_shard(bad), npf::Error) << bad;
    for (std::size_t count : {0u, 1u, 5u, 62u}) {
        for (int n : {1, 2, 3, 7}) {
            std::set<std::size_t> all;
            for (int k = 0; k < n; ++k) {
                for (std::size_t i : batch::shard_members(count, {k, n})) {
                    EXPECT_EQ(int(i % std::size_t(n)), k);
                    EXPECT_TRUE(all.insert(i).second);
                }
            }
            EXPECT_EQ(all.size(), count);
        }
    }
}

batch::MaterialResult result(const std::string& name, batch::MaterialStatus status, int shard) {
    batch::MaterialResult m;
    m.name = name;
    m.status = status;
    m.shard = shard;
    m.input = "/in/" + name + ".bsdf";
    m.output = "/out/" + name + ".exr";
    m.input_bytes = 1000;
    m.output_bytes = status == batch::MaterialStatus::Failed ? 0 : 10;
    if (status == batch::MaterialStatus::Failed) m.reason = "file \"x\": truncated\tline\n2";
    else m.error_mean = 0.0125, m.error_max = 0.02, m.psnr = 35.5, m.ssim = 0.97, m.relmse = 1e-3;
    m.seconds = 1.5;
    m.hash = "abc";
    return m;
}

TEST(BatchSummary, JsonRoundTripsAndMarkdownNamesEveryMaterial) {
    batch::BatchSummary s;
    s.config = "/c/batch.yaml";
    s.shard_index = 1, s.shard_count = 2, s.shards = {1};
    s.config_materials = 4;
    s.seconds = 3.25;
    s.warnings = {"w \"1\""};
    s.materials = {result("a", batch::MaterialStatus::Converted, 1), result("b|c", batch::MaterialStatus::Failed, 1)};
    s.materials[0].edits = {"rotate 30 degrees"};
    const std::string path = folder() + "/summary";
    batch::write_summary(s, path);
    const batch::BatchSummary r = batch::read_summary_json(path + ".json");
    EXPECT_EQ(batch::summary_json(r), batch::summary_json(s));
    EXPECT_FALSE(r.ok());
    EXPECT_EQ(r.count(batch::MaterialStatus::Failed), 1u);
    ASSERT_TRUE(r.materials[0].ratio());
    EXPECT_DOUBLE_EQ(*r.materials[0].ratio(), 100.0);
    EXPECT_FALSE(r.materials[1].ratio());
    const std::string md = npf::testing::read_text(path + ".md");
    EXPECT_TRUE(contains(md, "| a | converted | 1.50 |")) << md;
    EXPECT_TRUE(contains(md, "| b/c | failed |")) << md;
    EXPECT_TRUE(contains(md, "1/100.0")) << md;
    EXPECT_TRUE(contains(md, "1.25 / 2.00")) << md;
    EXPECT_TRUE(contains(md, "some materials failed")) << md;
    EXPECT_THROW(batch::read_summary_json(folder() + "/none.json"), npf::Error);
    npf::testing::write_text(folder() + "/bad.json", "{\"something\": 1}");
    EXPECT_THROW(batch::read_summary_json(folder() + "/bad.json"), npf::Error);
}

TEST(BatchSummary, MergeJoinsShardsAndWarnsAboutGaps) {
    batch::BatchSummary a, b;
    a.config = b.config = "/c.yaml";
    a.shard_count = b.shard_count = 3;
    a.config_materials = b.config_materials = 3;
    a.shard_index = 0, a.shards = {0};
    b.shard_index = 2, b.shards = {2};
    a.materials = {result("m0", batch::MaterialStatus::Converted, 0)};
    b.materials = {result("m2", batch::MaterialStatus::Skipped, 2)};
    const batch::BatchSummary m = batch::merge_summaries({b, a});
    ASSERT_EQ(m.materials.size(), 2u);
    EXPECT_EQ(m.materials[0].name, "m0");
    EXPECT_EQ(m.materials[1].name, "m2");
    EXPECT_EQ(m.shards, (std::vector<int>{0, 2}));
    bool missing = false;
    for (const std::string& w : m.warnings) missing |= contains(w, "shard 1 of 3 is missing");
    EXPECT_TRUE(missing);
    EXPECT_THROW(batch::merge_summaries({}), npf::Error);
}

}  // namespace

namespace {

// A conversion that gains light is flagged in the Markdown summary and its albedo survives the
// JSON round trip; one that does not is left alone.
TEST(BatchSummary, FlagsConversionsThatGainLight) {
    batch::BatchSummary s;
    s.config = "cfg.yaml";
    for (double albedo : {1.18, 0.73}) {
        batch::MaterialResult m;
        m.name = albedo > 1.0 ? "bright" : "dark";
        m.status = batch::MaterialStatus::Converted;
        m.albedo_max = albedo;
        s.materials.push_back(m);
    }
    const std::string md = batch::summary_markdown(s);
    EXPECT_TRUE(contains(md, "albedo 1.180 > 1: gains light")) << md;
    EXPECT_FALSE(contains(md, "albedo 0.730")) << md;
    const std::string dir = npf::testing::temporary_folder("batch-summary");
    batch::write_summary(s, dir + "/summary");
    const batch::BatchSummary back = batch::read_summary_json(dir + "/summary.json");
    ASSERT_EQ(back.materials.size(), 2u);
    ASSERT_TRUE(back.materials[0].albedo_max);
    EXPECT_DOUBLE_EQ(*back.materials[0].albedo_max, 1.18);
}

}  // namespace
