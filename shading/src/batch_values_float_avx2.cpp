// The float lanes' table lookups (values_float_avx2): batch_values_avx2.cpp's templates compiled
// with FMA and contracted multiply-adds (CMakeLists.txt), which the float budget of
// docs/shading.md allows and the double path's bits do not. Called only where the CPU has AVX2
// and FMA (npf_batch.cpp).
#define NPF_BATCH_VALUES_FLOAT
#include "batch_values_avx2.cpp"
