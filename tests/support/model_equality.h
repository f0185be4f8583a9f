// Bit-for-bit equality of two NPF models' stored factors, for the edit tests that expect an
// edit (an identity, a round trip) to change nothing.
#pragma once

#include <npf/shading/npf_model.h>

namespace npf::testing {

// rho_d, rho_s, F, and the bases and weights of D and G are equal, bit for bit (one expectation
// each, so that a failure names the factor).
void expect_same_factors(const NpfModel& a, const NpfModel& b);

}  // namespace npf::testing
