// Factor textures read and shade the same in a caller whose threads flush denormals to zero
// (x86 FTZ and DAZ, as Mitsuba's scene-loading threads and many renderers run): the detail layer's
// half-denormal texels once read as 0 there (float_environment.h).
#include <npf/core/float_environment.h>
#include <npf/shading/npf_closure.h>
#include <npf/shading/npf_texture_file.h>

#include "npf_test_factors.h"
#include "synthetic_rgl.h"

#include <npf/fit/spectral_compression.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#ifdef NPF_HAS_MXCSR

namespace {

using npf::NpfClosure, npf::NpfModel, npf::Vec3;

// A model whose detail basis holds values exact in half, most of them half denormals (below
// 6.1e-5), with weights large enough that they matter: the writer stores such a basis as half.
NpfModel model_with_denormal_detail() {
    NpfModel m = npf::compress_factors(npf::testing::make_test_factors({false, 3, false, 1}), {});
    m.detail_grid = npf::DetailGrid{4, 4, 8};
    m.detail.rank = 1;
    m.detail.cells = m.detail_grid.cells();
    for (std::size_t c = 0; c < m.detail.cells; ++c) m.detail.basis.push_back(float(std::ldexp(double(c % 97 + 1), -24)));
    m.detail.weights = {2000.f, 2500.f, 3000.f};
    m.detail.singular_values = {1.0, 0.0, 0.0};  // min(cells, channels) of them
    m.detail.kept_ratio = 1.0;
    return m;
}

class FlushDenormals {
public:
    FlushDenormals() : m_saved(_mm_getcsr()) {
        _mm_setcsr(m_saved | npf::ExactFloatScope::kFlushToZero | npf::ExactFloatScope::kDenormalsAreZero);
    }
    ~FlushDenormals() { _mm_setcsr(m_saved); }

private:
    unsigned m_saved;
};

std::vector<float> values_at(const NpfClosure& c, const std::vector<std::pair<Vec3, Vec3>>& pairs) {
    std::vector<float> out;
    float v[3];
    for (const auto& [view, light] : pairs) {
        c.eval(view, light, npf::WavelengthRequest::stored(), v);
        out.insert(out.end(), v, v + 3);
    }
    return out;
}

TEST(FloatEnvironment, FactorTexturesReadAndShadeTheSameWhenTheCallerFlushesDenormals) {
    const std::string path = npf::testing::temporary_folder("npf-float-env") + "/detail.exr";
    npf::write_npf_texture(model_with_denormal_detail(), path);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    auto direction = [&] {
        const float a = u(rng), b = u(rng), s = std::sqrt(a);
        return Vec3(s * std::cos(6.2831853f * b), s * std::sin(6.2831853f * b), std::sqrt(1.f - a));
    };
    std::vector<std::pair<Vec3, Vec3>> pairs;
    for (int i = 0; i < 200; ++i) pairs.emplace_back(direction(), direction());

    for (NpfClosure::Path path_kind : {NpfClosure::Path::Memory, NpfClosure::Path::Texture}) {
        const NpfClosure normal(path, path_kind);
        const std::vector<float> expected = values_at(normal, pairs);
        FlushDenormals flush;
        const NpfClosure flushed(path, path_kind);
        EXPECT_EQ(values_at(flushed, pairs), expected) << (path_kind == NpfClosure::Path::Memory ? "memory" : "texture");
        if (path_kind == NpfClosure::Path::Memory) {
            EXPECT_EQ(flushed.model().detail.basis, normal.model().detail.basis);
        }
    }
    // The caller's setting is back after the closure's work.
    FlushDenormals flush;
    const NpfClosure c(path, NpfClosure::Path::Memory);
    EXPECT_TRUE(_mm_getcsr() & npf::ExactFloatScope::kDenormalsAreZero);
}

}  // namespace

#endif
