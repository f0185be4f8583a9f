#include "model_equality.h"

#include <gtest/gtest.h>

namespace npf::testing {

void expect_same_factors(const NpfModel& a, const NpfModel& b) {
    EXPECT_EQ(a.rho_d, b.rho_d);
    EXPECT_EQ(a.rho_s, b.rho_s);
    EXPECT_EQ(a.F, b.F);
    EXPECT_EQ(a.D.basis, b.D.basis);
    EXPECT_EQ(a.D.weights, b.D.weights);
    EXPECT_EQ(a.G.basis, b.G.basis);
    EXPECT_EQ(a.G.weights, b.G.weights);
}

}  // namespace npf::testing
