// Spectral compression of D and G (paper sec. 3.4) and the NpfModel evaluation: full rank gives
// the fitted tables back, a family of known rank is found and recovered exactly, the ratio picks
// ranks as documented, and the compressed model evaluates as the factors do.
#include "npf_test_factors.h"

#include <npf/fit/spectral_compression.h>
#include <npf/core/error.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/detail_grid.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace {

using npf::CompressionOptions, npf::NpfFactors, npf::NpfModel, npf::SpectralBasis, npf::Vec3,
      npf::testing::make_test_factors, npf::testing::TestFactorSpec;

std::vector<TestFactorSpec> all_kinds() {
    return {{false, 3, false, 1}, {true, 3, false, 2}, {false, 20, true, 3}, {true, 20, true, 4}};
}

std::string kind_name(const TestFactorSpec& s) {
    return std::string(s.anisotropic ? "anisotropic" : "isotropic") + (s.spectral ? " spectral" : " rgb");
}

// Largest relative difference between the reconstruction and the tables.
double max_relative_error(const SpectralBasis& s, const std::vector<float>& tables, std::size_t channels) {
    double worst = 0.0;
    for (std::size_t c = 0; c < channels; ++c) {
        for (std::size_t i = 0; i < s.cells; ++i) {
            const double want = tables[c * s.cells + i];
            worst = std::max(worst, std::fabs(s.at(c, i) - want) / std::fabs(want));
        }
    }
    return worst;
}

Vec3 random_direction(std::mt19937& rng) {
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    return npf::spherical_direction(0.49f * npf::kPi * uni(rng), 2.f * npf::kPi * uni(rng));
}

npf::Vec3d to_double(const Vec3& v) { return {v.x, v.y, v.z}; }

TEST(SpectralCompression, FullRankReproducesTheTables) {
    for (const TestFactorSpec& kind : all_kinds()) {
        SCOPED_TRACE(kind_name(kind));
        const NpfFactors f = make_test_factors(kind);
        const NpfModel m = npf::compress_factors(f, CompressionOptions());
        const std::size_t C = f.channel_count();
        EXPECT_EQ(std::size_t(m.D.rank), std::min(f.d_size(), C));
        EXPECT_EQ(std::size_t(m.G.rank), std::min(f.g_size(), C));
        EXPECT_DOUBLE_EQ(m.D.kept_ratio, 1.0);
        EXPECT_LT(max_relative_error(m.D, f.D, C), 1e-5);
        EXPECT_LT(max_relative_error(m.G, f.G, C), 1e-5);
        EXPECT_EQ(m.rho_d, f.rho_d);
        EXPECT_EQ(m.rho_s, f.rho_s);
        EXPECT_EQ(m.F, f.F);
        EXPECT_NO_THROW(m.validate("test"));
    }
}

// D_c = sum_{j<k} a_cj f_j: a family of exactly rank k.
TEST(SpectralCompression, KnownRankIsFoundAndRecovered) {
    NpfFactors f = make_test_factors({true, 20, true, 7});
    const std::size_t C = f.channel_count(), cells = f.d_size();
    constexpr int k = 4;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> uni(0.5, 1.5);
    std::vector<std::vector<double>> shapes(k, std::vector<double>(cells));
    for (int j = 0; j < k; ++j) {
        for (std::size_t i = 0; i < cells; ++i) shapes[j][i] = 1.0 + 0.8 * std::sin(0.37 * (j + 1) * double(i) + j);
    }
    for (std::size_t c = 0; c < C; ++c) {
        std::vector<double> a(k);
        for (double& x : a) x = uni(rng);
        for (std::size_t i = 0; i < cells; ++i) {
            double v = 0.0;
            for (int j = 0; j < k; ++j) v += a[std::size_t(j)] * shapes[std::size_t(j)][i];
            f.D[c * cells + i] = float(v);
        }
    }
    CompressionOptions o;
    o.d_ratio = 1.0 - 1e-9;
    const NpfModel by_ratio = npf::compress_factors(f, o);
    EXPECT_EQ(by_ratio.D.rank, k);
    EXPECT_LT(max_relative_error(by_ratio.D, f.D, C), 1e-5);
    // The singular values past k are float noise.
    EXPECT_LT(by_ratio.D.singular_values[k] / by_ratio.D.singular_values[0], 1e-6);

    o = CompressionOptions();
    o.d_rank = k;
    EXPECT_LT(max_relative_error(npf::compress_factors(f, o).D, f.D, C), 1e-5);
    o.d_rank = k - 1;
    EXPECT_GT(max_relative_error(npf::compress_factors(f, o).D, f.D, C), 1e-3);
}

// Per channel: every channel's own table keeps the ratio, at the smallest rank that does; a dim
// channel whose shape differs from the bright ones' (a colour shift) is not dropped.
TEST(SpectralCompression, PerChannelRuleHoldsForEveryChannel) {
    const std::size_t cells = 64, C = 6;
    std::vector<float> tables(C * cells);
    for (std::size_t c = 0; c < C; ++c) {
        for (std::size_t i = 0; i < cells; ++i) {
            const double x = double(i) / cells;
            const double narrow = std::exp(-40.0 * x * x), wide = std::exp(-2.0 * x);
            // Five bright channels share the narrow lobe; the last, dim, is mostly the wide one.
            tables[c * cells + i] = float(c + 1 < C ? 10.0 * narrow + 0.1 * wide : 0.2 * narrow + wide);
        }
    }
    const npf::SpectralBasis total = npf::compress_tables(tables, C, cells, 0.99, 0, false);
    const npf::SpectralBasis each = npf::compress_tables(tables, C, cells, 0.99, 0, true);
    EXPECT_EQ(total.rank, 1);  // the bright channels rule the total
    EXPECT_EQ(each.rank, 2);
    for (const npf::SpectralBasis* b : {&total, &each}) {
        double worst = 1.0;
        for (std::size_t c = 0; c < C; ++c) {
            double err = 0.0, norm = 0.0;
            for (std::size_t i = 0; i < cells; ++i) {
                const double want = tables[c * cells + i];
                err += (b->at(c, i) - want) * (b->at(c, i) - want);
                norm += want * want;
            }
            worst = std::min(worst, 1.0 - err / norm);
        }
        if (b == &each) EXPECT_GE(worst, 0.99 - 1e-6);
        else EXPECT_LT(worst, 0.99);
    }
}

TEST(SpectralCompression, RanksGrowWithTheRatioAndReachIt) {
    const NpfFactors f = make_test_factors({true, 20, true, 5});
    int previous = 0;
    for (double ratio : {0.5, 0.9, 0.99, 0.999, 0.9999, 0.99999, 0.999999, 1.0}) {
        SCOPED_TRACE(ratio);
        CompressionOptions o;
        o.d_ratio = o.g_ratio = ratio;
        o.per_channel = false;  // the paper's rule: the total (per channel: the next test)
        const NpfModel m = npf::compress_factors(f, o);
        EXPECT_GE(m.D.rank, previous);
        previous = m.D.rank;
        EXPECT_GE(m.D.kept_ratio, ratio - 1e-15);
        EXPECT_GE(m.G.kept_ratio, ratio - 1e-15);
        // The smallest such rank: one component less would not reach the ratio.
        double below = 0.0, total_energy = 0.0;
        for (std::size_t k = 0; k < m.D.singular_values.size(); ++k) {
            const double e = m.D.singular_values[k] * m.D.singular_values[k];
            total_energy += e;
            if (int(k) < m.D.rank - 1) below += e;
        }
        if (ratio < 1.0) {
            EXPECT_LT(below / total_energy, ratio);
        }
        // Eckart-Young: the squared error left is exactly the dropped share.
        double err = 0.0, total = 0.0;
        for (std::size_t c = 0; c < f.channel_count(); ++c) {
            for (std::size_t i = 0; i < f.d_size(); ++i) {
                const double want = f.D[c * f.d_size() + i];
                err += (m.D.at(c, i) - want) * (m.D.at(c, i) - want);
                total += want * want;
            }
        }
        EXPECT_NEAR(err / total, 1.0 - m.D.kept_ratio, 1e-6);
    }
    EXPECT_EQ(previous, 20);
}

TEST(SpectralCompression, RankForRatio) {
    const std::vector<double> s = {3.0, 2.0, 1.0};  // shares 9/14, 13/14, 1
    EXPECT_EQ(npf::rank_for_ratio(s, 0.5), 1);
    EXPECT_EQ(npf::rank_for_ratio(s, 9.0 / 14.0), 1);
    EXPECT_EQ(npf::rank_for_ratio(s, 0.7), 2);
    EXPECT_EQ(npf::rank_for_ratio(s, 0.95), 3);
    EXPECT_EQ(npf::rank_for_ratio(s, 1.0), 3);
    EXPECT_EQ(npf::rank_for_ratio({0.0, 0.0}, 0.9), 1);
    EXPECT_EQ(npf::rank_for_ratio({0.0, 0.0}, 1.0), 2);
}

TEST(SpectralCompression, SignsAreFixedAndOutputDeterministic) {
    const NpfFactors f = make_test_factors({true, 20, true, 9});
    const NpfModel a = npf::compress_factors(f, CompressionOptions());
    const NpfModel b = npf::compress_factors(f, CompressionOptions());
    for (const SpectralBasis* s : {&a.D, &a.G}) {
        for (int k = 0; k < s->rank; ++k) {
            const float* u = s->basis.data() + std::size_t(k) * s->cells;
            std::size_t largest = 0;
            for (std::size_t i = 1; i < s->cells; ++i) {
                if (std::fabs(u[i]) > std::fabs(u[largest])) largest = i;
            }
            EXPECT_GT(u[largest], 0.f) << "component " << k;
        }
    }
    EXPECT_EQ(a.D.basis, b.D.basis);
    EXPECT_EQ(a.D.weights, b.D.weights);
    EXPECT_EQ(a.G.basis, b.G.basis);
    EXPECT_EQ(a.G.weights, b.G.weights);
}

TEST(SpectralCompression, OptionsAreChecked) {
    const NpfFactors f = make_test_factors({false, 3, false, 1});
    CompressionOptions o;
    o.d_rank = 1000;  // clamped to min(cells, channels)
    EXPECT_EQ(npf::compress_factors(f, o).D.rank, 3);
    for (double bad : {0.0, -0.5, 1.5, std::nan("")}) {
        o = CompressionOptions();
        o.g_ratio = bad;
        EXPECT_THROW(npf::compress_factors(f, o), npf::Error) << bad;
    }
    o = CompressionOptions();
    o.d_rank = -1;
    EXPECT_THROW(npf::compress_factors(f, o), npf::Error);
    NpfFactors broken = f;
    broken.G.pop_back();
    EXPECT_THROW(npf::compress_factors(broken, CompressionOptions()), npf::Error);
}

TEST(NpfModel, EvaluatesAsTheFactorsAtFullRank) {
    for (const TestFactorSpec& kind : all_kinds()) {
        SCOPED_TRACE(kind_name(kind));
        const NpfFactors f = make_test_factors(kind);
        const NpfModel m = npf::compress_factors(f, CompressionOptions());
        const std::size_t C = f.channel_count();
        std::mt19937 rng(kind.seed);
        std::vector<double> all(C);
        for (int n = 0; n < 500; ++n) {
            const Vec3 wi = random_direction(rng), wo = random_direction(rng);
            m.eval_all(wi, wo, all.data());
            for (std::size_t c = 0; c < C; ++c) {
                const double want = f.eval(c, to_double(wi), to_double(wo));
                ASSERT_NEAR(all[c], want, 1e-5 * std::fabs(want)) << "channel " << c << " pair " << n;
                ASSERT_EQ(m.eval(c, wi, wo), all[c]);
            }
        }
        // Below the horizon: 0.
        m.eval_all({0.f, 0.6f, -0.8f}, {0.f, 0.f, 1.f}, all.data());
        for (double v : all) EXPECT_EQ(v, 0.0);
        EXPECT_EQ(m.eval(0, {0.f, 0.f, 1.f}, {0.6f, 0.f, 0.f}), 0.0);
    }
}

// Ranks above the cached limit (and lookups prepared without projection) take the corner-by-
// corner path; it must give the same values as the cached one.
TEST(NpfModel, LargeRanksEvaluateAlike) {
    const NpfFactors f = make_test_factors({true, 80, true, 21});
    const NpfModel m = npf::compress_factors(f, CompressionOptions());
    ASSERT_GT(m.D.rank, 64);
    std::mt19937 rng(5);
    for (int n = 0; n < 100; ++n) {
        const Vec3 wi = random_direction(rng), wo = random_direction(rng);
        NpfModel::Lookup cached, direct;
        ASSERT_TRUE(m.prepare(wi, wo, cached));
        ASSERT_TRUE(m.prepare(wi, wo, direct, /*project_bases=*/false));
        EXPECT_TRUE(cached.cached);
        EXPECT_FALSE(direct.cached);
        for (std::size_t c = 0; c < f.channel_count(); c += 7) {
            const double want = f.eval(c, to_double(wi), to_double(wo));
            ASSERT_NEAR(m.value(direct, c), want, 1e-5 * std::fabs(want));
            ASSERT_NEAR(m.value(cached, c), m.value(direct, c), 1e-12 * std::fabs(want));
        }
    }
}

// At low rank a reconstructed table may dip below zero; evaluation clamps D and G at 0.
// values() (every channel of a prepared pair, in vectorised blocks) is value() to the bit, on the
// cached and the direct lookups, with a detail layer (clamp included) and without; its `base` is the
// value of the same model without the layer. 150 channels: blocks of 64 and a partial one.
TEST(NpfModel, AllChannelsAtOnceAreEachChannelsValue) {
    NpfFactors f = make_test_factors({true, 150, true, 6});
    CompressionOptions rank_three;
    rank_three.d_rank = rank_three.g_rank = 3;
    const NpfModel plain = npf::compress_factors(f, rank_three);
    NpfModel detailed = plain;
    const npf::DetailGrid grid{5, 4, 6};
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> residual(-0.4f, 0.3f);  // model + residual below 0 in places
    std::vector<float> tables(f.channel_count() * grid.cells());
    for (float& v : tables) v = residual(rng);
    detailed.detail_grid = grid;
    detailed.detail = npf::compress_tables(tables, f.channel_count(), grid.cells(), 1.0, 4);
    const std::size_t C = f.channel_count();
    std::vector<double> all(C), base(C);
    int clamped = 0;
    for (int n = 0; n < 200; ++n) {
        const Vec3 wi = random_direction(rng), wo = random_direction(rng);
        for (const NpfModel* m : {&plain, static_cast<const NpfModel*>(&detailed)}) {
            for (bool project : {true, false}) {
                NpfModel::Lookup at, at_plain;
                ASSERT_TRUE(m->prepare(wi, wo, at, project));
                ASSERT_TRUE(plain.prepare(wi, wo, at_plain, project));
                m->values(at, all.data(), base.data());
                for (std::size_t c = 0; c < C; ++c) {
                    ASSERT_EQ(all[c], m->value(at, c)) << "channel " << c << (project ? ", cached" : ", direct");
                    ASSERT_EQ(base[c], plain.value(at_plain, c)) << "channel " << c;
                    clamped += m == &detailed && all[c] == 0.0 && base[c] > 0.0;
                }
            }
        }
    }
    EXPECT_GT(clamped, 0);  // the layer's clamp at 0 was exercised
}

TEST(NpfModel, ReconstructionIsClampedAtZero) {
    NpfFactors f = make_test_factors({false, 3, false, 2});
    NpfModel m = npf::compress_factors(f, CompressionOptions());
    for (float& w : m.D.weights) w = -std::fabs(w);  // every reconstructed D < 0
    const Vec3 wi{0.f, 0.f, 1.f}, wo{0.3f, 0.f, 0.953939f};
    for (std::size_t c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(m.eval(c, wi, wo), m.rho_d[c]);
}

}  // namespace
