// The instruction set of npf's vector kernels (the batched closure's angles, the fitter's passes):
// one process-wide choice. Auto (the default) takes AVX2 where the CPU has it, else the portable
// build. Every kernel gives the same bits on either (the same arithmetic, no fused multiply-add),
// which the tests check by running both; benchmarks compare them.
#pragma once

namespace npf {

enum class SimdIsa { Auto, Portable, Avx2 };

bool simd_isa_supported(SimdIsa isa);
// Throws npf::Error for an instruction set this CPU lacks.
void set_simd_isa(SimdIsa isa);
// What Auto resolves to now: Portable or Avx2 (the environment variable NPF_SIMD=portable|avx2
// overrides the CPU's answer).
SimdIsa simd_isa();
const char* simd_isa_name(SimdIsa isa);
// Whether the CPU has fused multiply-add (the batched closure's float lanes are built with it and
// run only where it is; the double kernels never use it).
bool cpu_has_fma();

// Sets an instruction set for its lifetime, then restores Auto (tests, benchmarks).
class SimdIsaScope {
public:
    explicit SimdIsaScope(SimdIsa isa) { set_simd_isa(isa); }
    ~SimdIsaScope() { set_simd_isa(SimdIsa::Auto); }
    SimdIsaScope(const SimdIsaScope&) = delete;
    SimdIsaScope& operator=(const SimdIsaScope&) = delete;
};

}  // namespace npf
