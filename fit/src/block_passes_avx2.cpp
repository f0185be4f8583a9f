// The fitter's passes for AVX2: this file alone is compiled with -mavx2 and without FMA
// (converter/CMakeLists.txt), and its passes run only where the CPU has AVX2 (block_passes()).
#if defined(__AVX2__)
#define NPF_PASSES_NS avx2
#include "block_passes_impl.h"
#else
#include "block_passes.h"
#endif

namespace npf::fit_detail::avx2 {

template <int L>
const BlockPasses<L>* passes() {
#if defined(__AVX2__)
    return &kPasses<L>;
#else
    return nullptr;
#endif
}
template const BlockPasses<4>* passes<4>();
template const BlockPasses<16>* passes<16>();

}  // namespace npf::fit_detail::avx2
