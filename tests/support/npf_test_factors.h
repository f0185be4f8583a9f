// Small hand-made NPF factor sets for the compression, model and texture tests: smooth, random,
// strictly positive tables on tiny grids (D 8 x 1 or 8 x 16, F 6, G 8 x 1 or 8 x 12), RGB or
// spectral, in the gauge of the fitter's output (G = 1 and F = 1 at normal incidence are not
// enforced: nothing here depends on it).
#pragma once

#include <npf/converter/fit/npf_factors.h>

#include <cstddef>

namespace npf::testing {

struct TestFactorSpec {
    bool anisotropic = false;
    std::size_t channels = 3;  // 3 with spectral = false: RGB
    bool spectral = false;     // wavelengths 400, 415, ... nm
    unsigned seed = 1;
};

NpfFactors make_test_factors(const TestFactorSpec& spec);

}  // namespace npf::testing
