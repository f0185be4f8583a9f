#include <npf/core/simd_isa.h>

#include <npf/core/error.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace npf {

namespace {

std::atomic<int> g_isa{int(SimdIsa::Auto)};

// Whether the CPU has `feature` (a string literal, as __builtin_cpu_supports takes it); false
// where the compiler cannot ask.
#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
#define NPF_CPU_SUPPORTS(feature) __builtin_cpu_supports(feature)
#else
#define NPF_CPU_SUPPORTS(feature) false
#endif

bool cpu_has_avx2() {
    static const bool has = NPF_CPU_SUPPORTS("avx2");
    return has;
}

// NPF_SIMD=portable or avx2 sets what Auto means for the process (benchmarks, and reproducing a
// result across machines); anything else, or avx2 on a CPU without it, is reported once and
// ignored.
SimdIsa auto_isa() {
    static const SimdIsa isa = [] {
        const SimdIsa detected = cpu_has_avx2() ? SimdIsa::Avx2 : SimdIsa::Portable;
        const char* env = std::getenv("NPF_SIMD");
        if (env == nullptr || *env == '\0') return detected;
        if (std::strcmp(env, "portable") == 0) return SimdIsa::Portable;
        if (std::strcmp(env, "avx2") == 0 && cpu_has_avx2()) return SimdIsa::Avx2;
        std::fprintf(stderr, "npf: warning: NPF_SIMD=%s ignored (portable, or avx2 where the CPU has it); using %s\n", env,
                     detected == SimdIsa::Avx2 ? "avx2" : "portable");
        return detected;
    }();
    return isa;
}

}  // namespace

bool cpu_has_fma() {
    static const bool has = NPF_CPU_SUPPORTS("fma");
    return has;
}

bool simd_isa_supported(SimdIsa isa) { return isa != SimdIsa::Avx2 || cpu_has_avx2(); }

void set_simd_isa(SimdIsa isa) {
    if (!simd_isa_supported(isa)) throw Error("vector kernels", "this CPU has no AVX2");
    g_isa = int(isa);
}

SimdIsa simd_isa() {
    const auto isa = SimdIsa(g_isa.load());
    return isa != SimdIsa::Auto ? isa : auto_isa();
}

const char* simd_isa_name(SimdIsa isa) {
    switch (isa) {
    case SimdIsa::Auto: return "auto";
    case SimdIsa::Portable: return "portable";
    case SimdIsa::Avx2: return "avx2";
    }
    return "?";
}

}  // namespace npf
