// HalfVectorGrid (shading/npf_albedo.h): the half-vector quadrature's nodes that
// npf_directional_albedo and the detail fit's energy rows share. Its weights, 4 (wi . h)
// d(omega_h) cos(theta_o), integrate cos(theta_o) over the hemisphere (pi) at any view up to
// grazing, the mirror directions lie above the horizon asked for, and the nodes are those of
// the midpoint rule in (u, phi_h).
#include <npf/shading/npf_albedo.h>
#include <npf/shading/npf_equation.h>

#include <gtest/gtest.h>

#include <cmath>

namespace {

double cosine_integral(const npf::HalfVectorGrid& grid, double theta_view) {
    const double ix = std::sin(theta_view), iy = 0.0, iz = std::cos(theta_view);
    double sum = 0.0;
    grid.for_each_node(ix, iy, iz, 0.0, [&](const npf::HalfVectorNode& n) {
        const double solid = n.sin_theta_h * npf::kPiD * n.u * grid.du() * grid.dphi();  // d(omega_h)
        sum += 4.0 * n.cos_ih * solid * n.oz;
    });
    return sum;
}

}  // namespace

TEST(HalfVectorGrid, IntegratesTheCosineOverTheHemisphere) {
    const npf::HalfVectorGrid grid(128, 128);
    for (double deg : {0.0, 30.0, 60.0, 80.0, 89.0}) {
        EXPECT_NEAR(cosine_integral(grid, deg * npf::kPiD / 180.0), npf::kPiD, 2e-3 * npf::kPiD) << deg << " degrees";
    }
}

TEST(HalfVectorGrid, NodesAreTheMidpointsAndMirrorAboveTheHorizon) {
    const npf::HalfVectorGrid grid(16, 8);
    EXPECT_EQ(grid.du(), 1.0 / 16);
    EXPECT_EQ(grid.dphi(), 2.0 * npf::kPiD / 8);
    const double ix = std::sin(1.2), iz = std::cos(1.2);
    int count = 0;
    grid.for_each_node(ix, 0.0, iz, 0.05, [&](const npf::HalfVectorNode& n) {
        ++count;
        const double k = std::round(n.u / grid.du() - 0.5);
        EXPECT_EQ(n.u, (k + 0.5) * grid.du());
        EXPECT_EQ(n.sin_theta_h, std::sin(npf::equation::theta_h_of_u(n.u)));
        EXPECT_GT(n.cos_ih, 0.0);
        EXPECT_GT(n.oz, 0.05);
        EXPECT_NEAR(n.ox * n.ox + n.oy * n.oy + n.oz * n.oz, 1.0, 1e-12);
    });
    EXPECT_GT(count, 0);
    EXPECT_LT(count, 16 * 8);
}
