// The fitter's passes for any CPU, and the run-time choice between them and the AVX2 build.
#define NPF_PASSES_NS portable
#include "block_passes_impl.h"

#include <npf/core/simd_isa.h>

namespace npf::fit_detail {

namespace portable {
template <int L>
const BlockPasses<L>& passes() {
    return kPasses<L>;
}
template const BlockPasses<4>& passes<4>();
template const BlockPasses<16>& passes<16>();
}  // namespace portable

template <int L>
const BlockPasses<L>& block_passes() {
    if (simd_isa() == SimdIsa::Avx2) {
        if (const BlockPasses<L>* p = avx2::passes<L>()) return *p;
    }
    return portable::passes<L>();
}
template const BlockPasses<4>& block_passes<4>();
template const BlockPasses<16>& block_passes<16>();

}  // namespace npf::fit_detail
