// Renderers often run their threads with denormals flushed to zero (x86's FTZ and DAZ bits in
// MXCSR: Mitsuba's scene-loading threads, Embree, many production renderers), and that setting
// also applies to half-to-float conversion instructions: loading a factor texture there turned
// every half-denormal detail basis value (below 6.1e-5, over half of a typical detail layer) into
// 0 and changed its f_r by up to 4 % of its peak (issue 20, found through the Mitsuba plugin).
// ExactFloatScope turns both bits off for its lifetime and restores the caller's setting after,
// so that reading and shading give the same numbers in any caller's environment. Elsewhere than
// x86 (no MXCSR) it does nothing.
#pragma once

#if defined(__SSE__) || defined(_M_X64)
#include <xmmintrin.h>
#define NPF_HAS_MXCSR 1
#endif

namespace npf {

class ExactFloatScope {
public:
#ifdef NPF_HAS_MXCSR
    static constexpr unsigned kFlushToZero = 0x8000, kDenormalsAreZero = 0x0040;
    ExactFloatScope() : m_saved(_mm_getcsr()) {
        if (m_saved & (kFlushToZero | kDenormalsAreZero)) _mm_setcsr(m_saved & ~(kFlushToZero | kDenormalsAreZero));
    }
    ~ExactFloatScope() {
        if (m_saved & (kFlushToZero | kDenormalsAreZero)) _mm_setcsr(m_saved);
    }
#endif
    ExactFloatScope(const ExactFloatScope&) = delete;
    ExactFloatScope& operator=(const ExactFloatScope&) = delete;

private:
#ifdef NPF_HAS_MXCSR
    unsigned m_saved;
#endif
};

}  // namespace npf
