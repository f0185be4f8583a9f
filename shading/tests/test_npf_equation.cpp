// The model's one home (npf_equation.h): its axis maps, G's horizon rule and Eq. 1, and that the
// fitter's tables (NpfFactors), the stored model (NpfModel) and the edits' G closing agree on
// them at the places where a second copy would drift first: cell centres, the last half cell
// before the horizon, and the clamps.
#include <npf/fit/npf_factors.h>
#include <npf/fit/spectral_compression.h>
#include <npf/shading/npf_equation.h>
#include <npf/shading/npf_model.h>

#include <gtest/gtest.h>

#include <cmath>

namespace {

namespace eq = npf::equation;

TEST(NpfEquation, SquareRootMapAndCellCentresInvertEachOther) {
    for (int n : {1, 7, 90}) {
        for (int k = 0; k < n; ++k) {
            // A centre falls in its own cell, half way: at k + 1/2 cells.
            const npf::table::Lerp d = eq::d_row(eq::u_of_theta_h(eq::theta_h_centre(k, n)), n);
            EXPECT_NEAR(d.i0 + d.t, k, 1e-9) << n << " " << k;
            const npf::table::Lerp f = eq::f_row(eq::theta_centre(k, n), n);
            EXPECT_NEAR(f.i0 + f.t, k, 1e-9);
            EXPECT_EQ(eq::g_owner_row(eq::theta_centre(k, n), n), k);
            const npf::table::Lerp c = eq::column(eq::phi_centre(k, n), n);
            EXPECT_NEAR(c.i0 + c.t, k, 1e-9);
        }
    }
    EXPECT_DOUBLE_EQ(eq::theta_h_of_u(1.0), eq::kHalfPi);
    EXPECT_DOUBLE_EQ(eq::u_of_theta_h(eq::kHalfPi), 1.0);
}

TEST(NpfEquation, GFollowsTheLineThroughItsLastTwoRowsToTheHorizon) {
    const int n = 10;
    // The horizon is half a cell past the last centre.
    const npf::table::Lerp at_horizon = eq::g_row(eq::kHalfPi, n);
    EXPECT_EQ(at_horizon.i0, n - 2);
    EXPECT_DOUBLE_EQ(at_horizon.t, 1.5);
    EXPECT_DOUBLE_EQ(eq::g_at_horizon(0.6, 0.9), 1.5 * 0.6 - 0.5 * 0.9);
    // The closing scale puts the line's end at 0, and only lowers an open row.
    const double s = eq::g_closing_scale(0.6, 0.9);
    EXPECT_NEAR(eq::g_at_horizon(0.6 * s, 0.9), 0.0, 1e-15);
    EXPECT_LT(s, 1.0);
    EXPECT_GE(eq::g_closing_scale(0.2, 0.9), 1.0);  // already closed (0.2 <= 0.9 / 3)
    EXPECT_EQ(eq::g_closing_scale(0.0, 0.9), 0.0);
}

TEST(NpfEquation, ValueClampsTheInterpolatedFactorsAndTheDetailSum) {
    EXPECT_DOUBLE_EQ(eq::value(0.1, 2.0, 3.0, 0.5, 0.8, 0.9, 4.0), 0.1 + 2.0 * 3.0 * 0.5 * 0.8 * 0.9 * 4.0);
    EXPECT_DOUBLE_EQ(eq::value(0.1, 2.0, -3.0, 0.5, 0.8, 0.9, 4.0), 0.1);  // a recombined D below 0
    EXPECT_DOUBLE_EQ(eq::value(0.1, 2.0, 3.0, 0.5, -0.8, 0.9, 4.0), 0.1);
    EXPECT_DOUBLE_EQ(eq::with_detail(0.3, -0.5), 0.0);
    EXPECT_DOUBLE_EQ(eq::with_detail(0.3, 0.2), 0.5);
}

// A small anisotropic factor set whose G is open at the horizon in one column.
npf::NpfFactors open_horizon_factors() {
    npf::NpfFactors f;
    f.grid = {6, 4, 5, 4};
    f.g_theta = 5;
    f.g_phi = 4;
    f.channels = npf::Channels::rgb();
    f.rho_d = {0.05f, 0.1f, 0.2f};
    f.rho_s = {1.0f, 0.8f, 0.6f};
    const std::size_t C = 3;
    f.D.resize(C * f.d_size());
    f.F.resize(C * std::size_t(f.grid.theta_d));
    f.G.resize(C * f.g_size());
    for (std::size_t c = 0; c < C; ++c) {
        for (std::size_t i = 0; i < f.d_size(); ++i) f.D[c * f.d_size() + i] = float(1.0 + 0.3 * std::sin(0.7 * i + c));
        for (int i = 0; i < f.grid.theta_d; ++i) f.F[c * f.grid.theta_d + i] = float(1.0 + 0.1 * i);
        for (int r = 0; r < f.g_theta; ++r) {
            for (int j = 0; j < f.g_phi; ++j) {
                // Falling towards the horizon; column 1 stays high (open), the others close.
                const double g = j == 1 ? 1.0 - 0.02 * r : 1.0 - 0.24 * r;
                f.G[c * f.g_size() + std::size_t(r * f.g_phi + j)] = float(g);
            }
        }
    }
    return f;
}

TEST(NpfEquation, FitterTablesAndStoredModelEvaluateAlike) {
    const npf::NpfFactors f = open_horizon_factors();
    const npf::NpfModel m = npf::compress_factors(f, npf::CompressionOptions());
    // Pairs across the grid, including views in G's last half cell.
    for (double ti : {0.05, 0.6, 1.2, 1.55, 1.5700}) {
        for (double to : {0.1, 0.9, 1.56}) {
            for (double pi : {0.3, 2.0, 4.5}) {
                const npf::Vec3d wi{std::sin(ti) * std::cos(pi), std::sin(ti) * std::sin(pi), std::cos(ti)};
                const npf::Vec3d wo{std::sin(to) * std::cos(pi + 2.1), std::sin(to) * std::sin(pi + 2.1), std::cos(to)};
                const npf::Vec3 a(float(wi.x), float(wi.y), float(wi.z)), b(float(wo.x), float(wo.y), float(wo.z));
                const npf::Vec3d ad{a.x, a.y, a.z}, bd{b.x, b.y, b.z};
                for (std::size_t c = 0; c < 3; ++c) {
                    const double want = f.eval(c, ad, bd), got = m.eval(c, a, b);
                    EXPECT_NEAR(got, want, 1e-5 * std::max(1.0, want)) << ti << " " << to << " " << pi << " " << c;
                }
            }
        }
    }
}

TEST(NpfEquation, ClosingTheHorizonClosesEveryOpenColumnAndKeepsTheRest) {
    npf::NpfModel m = npf::compress_factors(open_horizon_factors(), npf::CompressionOptions());
    ASSERT_TRUE(m.g_open_at_horizon());
    const npf::NpfModel before = m;
    EXPECT_EQ(m.close_g_at_horizon(), 1);  // only column 1 was open
    EXPECT_FALSE(m.g_open_at_horizon());
    for (std::size_t c = 0; c < 3; ++c) {
        for (int j = 0; j < m.g_phi; ++j) EXPECT_LE(m.g_at_horizon(c, j), 0.0);
    }
    // Directions up to the centre of the row before the last are unchanged.
    const double theta = eq::theta_centre(m.g_theta - 2, m.g_theta);
    const npf::Vec3 w(float(std::sin(theta) * std::cos(1.9)), float(std::sin(theta) * std::sin(1.9)), float(std::cos(theta)));
    const npf::Vec3 n(0.f, 0.f, 1.f);
    for (std::size_t c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(float(m.eval(c, w, n)), float(before.eval(c, w, n)));
}

}  // namespace
