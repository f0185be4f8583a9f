// The render settings are declared once (render/include/npf/render/render_settings.h): `npf
// render`'s flags and a batch's render.* keys take the same values and refuse the same ones.
#include "run_tool.h"

#include <npf/batch/config.h>
#include <npf/core/error.h>
#include <npf/render/render_settings.h>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

namespace batch = npf::batch;
using npf::testing::describe;

struct Case {
    const char* key;    // render.KEY and --KEY
    std::string value;  // as given
    bool accepted;
};

const std::vector<Case>& cases() {
    static const std::vector<Case> all = {
        {"size", "1", true},       {"size", "16384", true},   {"size", "0", false},
        {"size", "16385", false}, {"size", " 5", false}, {"size", "5.0", false},
        {"spp", "1", true},        {"spp", "16777216", true}, {"spp", "0", false},
        {"spp", "16777217", false},
        {"seed", "0", true},       {"seed", "18446744073709551615", true},
        {"seed", "18446744073709551616", false}, {"seed", "-1", false},
        {"threads", "1", true},    {"threads", "1024", true}, {"threads", "0", false},
        {"threads", "1025", false},
    };
    return all;
}

// Whether a batch configuration takes `render: {KEY: "VALUE"}`, read as resolve_render_check reads it.
bool batch_takes(const Case& c) {
    const std::string yaml = "output_dir: out\ninputs: [a.bsdf]\ndefaults:\n  render: {" + std::string(c.key) + ": \"" + c.value + "\"}\n";
    try {
        const batch::BatchConfig config = batch::parse_batch_config(yaml, "cfg.yaml", "/tmp");
        batch::resolve_render_check(config.materials.at(0).settings);
        return true;
    } catch (const npf::Error&) {
        return false;
    }
}

TEST(RenderSettings, TheBatchAndNpfRenderTakeAndRefuseTheSameValues) {
    const std::string material = std::string(NPF_SOURCE_DIR) + "/configs/materials/brushed_copper.yaml";
    for (const Case& c : cases()) {
        const std::string flag = std::string("--") + c.key;
        // An output in a folder that does not exist: the flags are read first, so a value the
        // tool takes fails at -o instead, before any render.
        const npf::testing::ToolRun r = npf::testing::run_tool({"render", material, "-o", "/nonexistent-npf-folder/x.exr", flag, c.value});
        EXPECT_EQ(r.status, 1) << describe(r);
        const bool tool_takes = r.err.find(flag + ":") == std::string::npos;
        EXPECT_EQ(tool_takes, c.accepted) << flag << " '" << c.value << "'\n" << describe(r);
        EXPECT_EQ(batch_takes(c), c.accepted) << "render." << c.key << " '" << c.value << "'";
    }
}

TEST(RenderSettings, BothReadTheValueTheyTake) {
    const std::string yaml = "output_dir: out\ninputs: [a.bsdf]\ndefaults:\n  render: {size: 48, spp: 7, seed: 18446744073709551615, threads: 3}\n";
    const batch::RenderCheck check = batch::resolve_render_check(batch::parse_batch_config(yaml, "cfg.yaml", "/tmp").materials.at(0).settings);
    EXPECT_EQ(check.size, 48u);
    EXPECT_EQ(check.spp, 7u);
    EXPECT_EQ(check.seed, ~std::uint64_t(0));
    EXPECT_EQ(check.threads, 3u);
    EXPECT_EQ(npf::render::parse_image_size("48", "--size"), (std::pair<std::size_t, std::size_t>{48, 48}));
    EXPECT_EQ(npf::render::parse_image_size("32x16", "--size"), (std::pair<std::size_t, std::size_t>{32, 16}));
    EXPECT_THROW(npf::render::parse_image_size("32x0", "--size"), npf::Error);
}

}  // namespace
