// Re-compression without refitting: from a lossless file it must give what the converter's own
// compression of the same fit gives.
#include "npf_test_factors.h"

#include <npf/fit/spectral_compression.h>
#include <npf/edit/compression.h>
#include <npf/edit/recipe.h>

#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace {

// A spectral material whose D and G tables differ by wavelength (so the rank matters).
npf::NpfFactors varied_factors() {
    npf::testing::MicrofacetSpec s;
    s.spectral = true;
    s.channels = 12;
    s.alpha_x = 0.2;
    s.alpha_y = 0.4;
    s.d_phi = s.g_phi = 8;
    npf::NpfFactors f = npf::testing::make_microfacet_factors(s);
    const std::size_t C = f.rho_d.size(), d_cells = f.D.size() / C, g_cells = f.G.size() / C;
    for (std::size_t c = 0; c < C; ++c) {
        for (std::size_t i = 0; i < d_cells; ++i) f.D[c * d_cells + i] *= float(1.0 + 0.3 * std::sin(0.5 * c + 0.01 * i));
        for (std::size_t i = 0; i < g_cells; ++i) f.G[c * g_cells + i] *= float(1.0 - 0.2 * std::cos(0.3 * c + 0.02 * i));
    }
    return f;
}

double worst_relative(const npf::NpfModel& a, const npf::NpfModel& b) {
    double worst = 0.0, scale = 0.0;
    for (std::size_t c = 0; c < a.channel_count(); ++c) {
        for (std::size_t i = 0; i < a.D.cells; ++i) {
            worst = std::max(worst, std::fabs(a.D.at(c, i) - b.D.at(c, i)));
            scale = std::max(scale, std::fabs(b.D.at(c, i)));
        }
    }
    return worst / scale;
}

TEST(EditCompression, FromALosslessFileEqualsTheConvertersCompression) {
    const npf::NpfFactors f = varied_factors();
    npf::CompressionOptions lossless;
    const npf::NpfModel full = npf::compress_factors(f, lossless);
    ASSERT_GT(full.D.rank, 3);
    for (int rank : {1, 2, 3}) {
        npf::CompressionOptions o;
        o.d_rank = o.g_rank = rank;
        npf::edit::EditRecord rec;
        const npf::NpfModel edited = npf::edit::compress_model(full, o, &rec);
        const npf::NpfModel direct = npf::compress_factors(f, o);
        EXPECT_EQ(edited.D.rank, rank);
        EXPECT_EQ(edited.G.rank, rank);
        EXPECT_LT(worst_relative(edited, direct), 1e-5) << "rank " << rank;
        EXPECT_NE(rec.summary.find("-> " + std::to_string(rank)), std::string::npos) << rec.summary;
        EXPECT_TRUE(rec.warnings.empty());
        EXPECT_EQ(edited.F, full.F);
        EXPECT_EQ(edited.rho_d, full.rho_d);
    }
    // A ratio picks the same rank as the converter would.
    npf::CompressionOptions by_ratio;
    by_ratio.d_ratio = 0.999;
    by_ratio.g_ratio = 0.99;
    EXPECT_EQ(npf::edit::compress_model(full, by_ratio).D.rank, npf::compress_factors(f, by_ratio).D.rank);
    // Lower rank first, then higher: what was dropped does not come back, and the record says so.
    npf::CompressionOptions one, three;
    one.d_rank = one.g_rank = 1;
    three.d_rank = three.g_rank = 3;
    npf::edit::EditRecord rec;
    const npf::NpfModel back = npf::edit::compress_model(npf::edit::compress_model(full, one), three, &rec);
    EXPECT_EQ(back.D.rank, 1);
    EXPECT_FALSE(rec.warnings.empty());
}

TEST(EditCompression, RecipeStepParsesAndRejectsBadValues) {
    const auto r = npf::edit::parse_edit_recipe("steps:\n  - compress: {rank: [2, 1]}\n  - compress: {pca: [0.99, 0.9]}\n",
                                                "r.yaml", ".");
    ASSERT_EQ(r.steps.size(), 2u);
    EXPECT_EQ(r.steps[0].kind, npf::edit::EditStep::Kind::Compress);
    EXPECT_EQ(r.steps[0].compression.d_rank, 2);
    EXPECT_EQ(r.steps[0].compression.g_rank, 1);
    EXPECT_DOUBLE_EQ(r.steps[1].compression.g_ratio, 0.9);
    for (const char* bad : {"steps:\n  - compress: {rank: [0, 1]}\n", "steps:\n  - compress: {pca: [1.5, 0.9]}\n",
                            "steps:\n  - compress: {rank: [2, 1], pca: [0.9, 0.9]}\n",
                            "steps:\n  - compress: {rank: [2]}\n"}) {
        try {
            npf::edit::parse_edit_recipe(bad, "r.yaml", ".");
            ADD_FAILURE() << "accepted: " << bad;
        } catch (const npf::Error& e) {
            EXPECT_NE(std::string(e.what()).find("r.yaml:2"), std::string::npos) << e.what();
        }
    }
}

}  // namespace

namespace {

// A step is its own operation: apply_edits runs whatever the step carries, so a new edit kind
// needs no field in EditStep and no case in apply_edits (issue 36). Here a kind no list knows,
// halving the diffuse albedo, runs through apply_edits with its history entry and albedo check.
TEST(EditSteps, AStepCarriesItsOwnOperation) {
    npf::testing::MicrofacetSpec spec;
    const npf::NpfModel model = npf::compress_factors(npf::testing::make_microfacet_factors(spec), npf::CompressionOptions{});
    npf::edit::EditStep halve;
    halve.label = "halve the diffuse albedo";
    halve.operation = [](const npf::NpfModel& m, const npf::edit::EditOptions&, npf::edit::EditRecord* rec) {
        npf::NpfModel out = m;
        for (float& v : out.rho_d) v *= 0.5f;
        if (rec) rec->summary = "rho_d x 0.5";
        return out;
    };
    const npf::edit::EditResult r = npf::edit::apply_edits(model, {halve});
    ASSERT_EQ(r.model.rho_d.size(), model.rho_d.size());
    for (std::size_t c = 0; c < model.rho_d.size(); ++c) EXPECT_EQ(r.model.rho_d[c], 0.5f * model.rho_d[c]);
    ASSERT_EQ(r.records.size(), 1u);
    EXPECT_NE(r.records[0].summary.find("rho_d x 0.5"), std::string::npos);
    EXPECT_EQ(r.history_keys, std::vector<std::string>{"edit_001"});
    npf::edit::EditStep empty;
    empty.label = "nothing";
    EXPECT_THROW(npf::edit::apply_edits(model, {empty}), npf::Error);
}

}  // namespace
