// The predicted render PSNR of a conversion and --target-psnr (issue 16, item 4): the prediction
// against an independent paired render at the full comparison's size, the detail ladder (a low
// target writes a smaller file than a high one, an unreachable one writes the best and says so),
// the summary and metadata, and bad values of the flag. Small grids and an analytic source keep
// each conversion to a second or two.
#include "run_tool.h"
#include "synthetic_rgl.h"
#include "target_ladder.h"

#include <npf/batch/config.h>
#include <npf/converter/convert.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/core/error.h>
#include <npf/render/default_environment.h>
#include <npf/render/image_metrics.h>
#include <npf/render/path_tracer.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_texture_file.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace {

using npf::testing::metadata_value, npf::testing::synthetic_lobe, npf::testing::synthetic_lobe_path;
using npf::ConvertReport, npf::ConvertSettings, npf::DetailGrid, npf::testing::contains,
      npf::testing::describe, npf::testing::ToolRun;

// A quick RGB fit: a coarse base (so that the detail layer has something to add) and a short ladder.
ConvertSettings small_settings() {
    ConvertSettings s = npf::testing::small_ladder_settings();
    s.error_pairs = 1000;
    s.detail.grid = DetailGrid{8, 4, 8};
    return s;
}

std::uintmax_t bytes(const std::string& path) { return std::filesystem::file_size(path); }

// The prediction is what the full comparison measures: the source and the written file rendered
// at 256 x 256, environment sampling, the same seed, compared by npf compare's PSNR. At 32
// samples per pixel instead of the documented 128, for speed: the full figure is then a little
// lower from noise (37.16 dB against 37.83 at 128 spp, measured; predicted 37.81).
TEST(TargetPsnr, PredictionMatchesAFullSizePairedRender) {
    const std::string dir = npf::testing::temporary_folder("target-psnr");
    const std::string out = dir + "/lobe.exr";
    ConvertSettings s = small_settings();
    s.prediction = npf::PsnrPredictionOptions{};  // the default render
    s.prediction.threads = 2;
    const ConvertReport r = npf::convert_material(synthetic_lobe(), out, s);
    ASSERT_TRUE(r.predicted);
    ASSERT_TRUE(std::isfinite(r.prediction.psnr));
    EXPECT_GT(r.prediction.floor_psnr, r.prediction.psnr);
    // The studio lighting's figure (the set's first) is the one this full render checks.
    ASSERT_FALSE(r.prediction.lightings.empty());
    const npf::LightingPrediction& studio = r.prediction.lightings[0];
    ASSERT_EQ(studio.lighting, "studio");

    const npf::render::EnvironmentMap env = npf::render::EnvironmentMap::load(npf::render::default_environment_map_path());
    npf::render::RenderOptions o;
    o.width = o.height = 256;
    o.spp = 32;
    o.seed = 1;
    o.threads = 2;
    o.sampling = npf::render::Sampling::Environment;
    const npf::NpfBrdf written(out);
    const npf::render::ImageMetrics full = npf::render::compare_images(npf::render::render(synthetic_lobe(), env, o).image,
                                                                       npf::render::render(written, env, o).image);
    EXPECT_NEAR(studio.psnr, full.psnr, 1.0) << "prediction " << r.prediction_settings;
    EXPECT_LE(r.prediction.psnr, studio.psnr);
}

// A target the base alone reaches writes no detail layer; one only a detail grid reaches writes
// that grid, a larger file; a target nothing reaches writes the best candidate and says so.
TEST(TargetPsnr, LadderPicksTheSmallestThatMeetsTheTarget) {
    const std::string dir = npf::testing::temporary_folder("target-psnr");
    ConvertSettings s = small_settings();

    s.target_psnr = 200.0;  // unreachable
    const ConvertReport best = npf::convert_material(synthetic_lobe(), dir + "/best.exr", s);
    ASSERT_EQ(best.target_candidates.size(), 3u);
    EXPECT_FALSE(best.target_met);
    double highest = 0.0;
    for (const ConvertReport::TargetCandidate& c : best.target_candidates) highest = std::max(highest, c.psnr);
    EXPECT_EQ(best.prediction.psnr, highest);
    const npf::NpfModel best_file = npf::read_npf_texture(dir + "/best.exr");
    EXPECT_EQ(metadata_value(best_file, "target_psnr_met"), "false");
    EXPECT_EQ(metadata_value(best_file, "target_psnr"), "200");
    const double base_psnr = best.target_candidates[0].psnr;
    ASSERT_GT(highest, base_psnr + 1.0) << "the detail layer should add to a coarse base";

    s.target_psnr = base_psnr - 0.5;
    const ConvertReport low = npf::convert_material(synthetic_lobe(), dir + "/low.exr", s);
    EXPECT_TRUE(low.target_met);
    EXPECT_FALSE(low.has_detail);
    EXPECT_EQ(low.target_candidates.size(), 1u);
    EXPECT_GE(low.prediction.psnr, s.target_psnr);

    s.target_psnr = highest - 0.01;
    const ConvertReport high = npf::convert_material(synthetic_lobe(), dir + "/high.exr", s);
    EXPECT_TRUE(high.target_met);
    EXPECT_TRUE(high.has_detail);
    EXPECT_GE(high.prediction.psnr, s.target_psnr);
    EXPECT_LT(bytes(dir + "/low.exr"), bytes(dir + "/high.exr"));
    const npf::NpfModel high_file = npf::read_npf_texture(dir + "/high.exr");
    EXPECT_EQ(metadata_value(high_file, "target_psnr_met"), "true");
    EXPECT_NEAR(std::stod(metadata_value(high_file, "target_psnr_reached")), high.prediction.psnr, 1e-4 * high.prediction.psnr);
}

TEST(TargetPsnr, RejectsBadTargets) {
    EXPECT_THROW(npf::parse_target_psnr("abc", "t"), npf::Error);
    EXPECT_THROW(npf::parse_target_psnr("-3", "t"), npf::Error);
    EXPECT_THROW(npf::parse_target_psnr("nan", "t"), npf::Error);
    EXPECT_THROW(npf::parse_target_psnr("inf", "t"), npf::Error);
    EXPECT_THROW(npf::parse_target_psnr("0", "t"), npf::Error);
    EXPECT_EQ(npf::parse_target_psnr("42.5", "t"), 42.5);
    ConvertSettings s = small_settings();
    s.target_psnr = -1.0;
    const std::string dir = npf::testing::temporary_folder("target-psnr");
    EXPECT_THROW(npf::convert_material(synthetic_lobe(), dir + "/bad.exr", s), npf::Error);
    EXPECT_FALSE(std::filesystem::exists(dir + "/bad.exr"));
}

// The batch key takes the flag's rule (one check, parse_target_psnr) and reaches the settings.
TEST(TargetPsnr, BatchKey) {
    const std::string dir = npf::testing::temporary_folder("target-psnr");
    const std::string head = "output_dir: out\ninputs: [" + synthetic_lobe_path() + "]\ndefaults:\n  target_psnr: ";
    const npf::batch::BatchConfig c = npf::batch::parse_batch_config(head + "45\n", "b.yaml", dir);
    ASSERT_EQ(c.materials.size(), 1u);
    EXPECT_EQ(npf::batch::resolve_convert_settings(c.materials[0].settings, true).target_psnr, 45.0);
    for (const char* bad : {"abc", "-1", ".nan"}) {
        try {
            npf::batch::parse_batch_config(head + bad + "\n", "b.yaml", dir);
            ADD_FAILURE() << bad << " accepted";
        } catch (const npf::Error& e) {
            EXPECT_TRUE(contains(e.what(), "target_psnr")) << e.what();
        }
    }
}

// ---- the command ---------------------------------------------------------------------------

const std::vector<std::string> kSmallFlags = {"--grid", "16,1,12,24", "--g-grid", "12,1", "--iterations", "30",
                                              "--threads", "2", "--quiet", "--error-pairs", "1000"};

ToolRun convert(const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {"convert", synthetic_lobe_path(), "-o", out};
    args.insert(args.end(), kSmallFlags.begin(), kSmallFlags.end());
    args.insert(args.end(), extra.begin(), extra.end());
    return npf::testing::run_tool(args);
}

TEST(TargetPsnrCli, BadValuesNameTheFlag) {
    const std::string dir = npf::testing::temporary_folder("target-psnr");
    for (const char* v : {"abc", "-5", "nan", "0"}) {
        const ToolRun r = convert(dir + "/x.exr", {"--target-psnr", v});
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_TRUE(contains(r.err, "--target-psnr")) << describe(r);
        EXPECT_EQ(npf::testing::lines_of(r.err).size(), 1u) << describe(r);
    }
    for (const std::vector<std::string>& clash : {std::vector<std::string>{"--target-psnr", "40", "--no-predict"},
                                                 std::vector<std::string>{"--target-psnr", "40", "--detail", "8,4,8"}}) {
        const ToolRun r = convert(dir + "/x.exr", clash);
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_TRUE(contains(r.err, "--target-psnr")) << describe(r);
    }
    for (const std::vector<std::string>& grids : {std::vector<std::string>{"--target-grids", "8x4x8"},
                                                  std::vector<std::string>{"--target-psnr", "40", "--target-grids", "16x8x16,8x4x8"},
                                                  std::vector<std::string>{"--target-psnr", "40", "--target-grids", "16x8"}}) {
        const ToolRun r = convert(dir + "/x.exr", grids);
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_TRUE(contains(r.err, "--target-grids")) << describe(r);
        EXPECT_EQ(npf::testing::lines_of(r.err).size(), 1u) << describe(r);
    }
    EXPECT_TRUE(npf::testing::folder_entries(dir).empty());
}

// The summary and the file give size, ratio, predicted PSNR with its settings, energy error and
// the target; --no-predict leaves the prediction out.
TEST(TargetPsnrCli, SummaryAndMetadata) {
    const std::string dir = npf::testing::temporary_folder("target-psnr");
    const ToolRun r = convert(dir + "/t.exr", {"--target-psnr", "10"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, "predicted   render PSNR")) << r.out;
    EXPECT_TRUE(contains(r.out, "seed 1")) << r.out;
    EXPECT_TRUE(contains(r.out, "energy      directional albedo within")) << r.out;
    EXPECT_TRUE(contains(r.out, "target      10.00 dB met")) << r.out;
    EXPECT_TRUE(r.err.empty()) << r.err;
    const npf::NpfModel m = npf::read_npf_texture(dir + "/t.exr");
    for (const char* key : {"predicted_psnr", "predicted_psnr_floor", "predicted_psnr_render", "energy_error",
                            "energy_error_view_theta", "energy_error_views", "target_psnr", "target_psnr_met",
                            "target_psnr_reached", "target_psnr_candidates"}) {
        EXPECT_NE(metadata_value(m, key), "(absent)") << key;
    }
    EXPECT_EQ(metadata_value(m, "target_psnr_met"), "true");

    const ToolRun quick = convert(dir + "/q.exr", {"--no-predict", "--detail", "8,4,8"});
    ASSERT_EQ(quick.status, 0) << describe(quick);
    EXPECT_FALSE(contains(quick.out, "predicted")) << quick.out;
    const npf::NpfModel q = npf::read_npf_texture(dir + "/q.exr");
    EXPECT_EQ(metadata_value(q, "predicted_psnr"), "(absent)");
    EXPECT_NE(metadata_value(q, "energy_error"), "(absent)");
}

// A target nothing reaches: status 0, one warning line, the file marked.
TEST(TargetPsnrCli, UnreachableTargetWarnsAndMarksTheFile) {
    const std::string dir = npf::testing::temporary_folder("target-psnr");
    const ToolRun r = convert(dir + "/u.exr", {"--target-psnr", "200", "--target-grids", "8x4x8,16x8x16"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, "NOT met")) << r.out;
    ASSERT_EQ(npf::testing::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_TRUE(contains(r.err, "warning: target 200.00 dB not reached")) << r.err;
    const npf::NpfModel m = npf::read_npf_texture(dir + "/u.exr");
    EXPECT_EQ(metadata_value(m, "target_psnr_met"), "false");
    EXPECT_TRUE(contains(metadata_value(m, "target_psnr_candidates"), "16x8x16:")) << metadata_value(m, "target_psnr_candidates");
}

}  // namespace
