#include <npf/core/simd_isa.h>

#include <npf/core/error.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace npf {

namespace {

std::atomic<int> g_isa{int(SimdIsa::Auto)};

bool cpu_has_avx2() {
#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
    static const bool has = __builtin_cpu_supports("avx2");
    return has;
#else
    return false;
#endif
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
#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
    static const bool has = __builtin_cpu_supports("fma");
    return has;
#else
    return false;
#endif
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
