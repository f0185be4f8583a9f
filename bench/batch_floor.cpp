// npf_bench_batch_floor: what bounds the batched eval from below (issue 19's note, docs/shading.md).
//
//   build/bench/npf_bench_batch_floor FACTORS.exr [--seconds S] [--profile-float ROUNDS]
//
// --profile-float: only ROUNDS passes of eval_batch in float lanes with the pdf over the pairs
// below (65,536 of them), for an instruction counter, whose count inside eval_batch over
// ROUNDS x 65,536 is the instructions a pair (docs/shading.md, issue 35's third session):
//   valgrind --tool=callgrind --toggle-collect='npf::NpfClosure::eval_batch*'
//       build/bench/npf_bench_batch_floor FACTORS.exr --profile-float 2   (one command line)
//
// Two measurements on one factor texture, memory path, random pairs over the hemisphere (4 hero
// wavelengths per pair on a spectral file, R, G, B on an RGB one):
// 1. Time per pair of the batched angle kernel alone (the angles of every lookup, as eval_batch
//    computes them), beside eval_batch without and with the pdf, in the same run, for both of
//    the batch's precisions (double lanes, and BatchPrecision::Float's float lanes): the angles
//    are a part no faster eval can skip.
// 2. The float lanes against the double path at these pairs: the BRDF-space relative RMS of the
//    difference (npf/core/brdf_comparison.h; the float budget of docs/shading.md allows 1e-4)
//    and the largest relative difference of one value; and the paired render (the key and rim
//    lights on the Sphere, no Monte Carlo, 128 x 128) through each precision: its PSNR (the budget
//    asks 80 dB or more).
#include "batch_angles.h"
#include "batched_brdf.h"

#include <npf/core/brdf_comparison.h>
#include <npf/core/simd_isa.h>
#include <npf/render/image_metrics.h>
#include <npf/render/lighting.h>
#include <npf/shading/npf_batch.h>
#include <npf/shading/npf_closure.h>
#include <npf/shading/npf_pair_angles.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr std::size_t kBatch = 1024;
constexpr std::size_t kBatches = 64;

struct Pairs {
    std::vector<float> vx, vy, vz, lx, ly, lz, hero;
};

Pairs random_pairs(std::size_t n, float nm_lo, float nm_hi) {
    Pairs p;
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    auto direction = [&](std::vector<float>& x, std::vector<float>& y, std::vector<float>& z) {
        const float a = u(rng), b = u(rng), sin_theta = std::sqrt(a);
        x.push_back(sin_theta * std::cos(6.2831853f * b));
        y.push_back(sin_theta * std::sin(6.2831853f * b));
        z.push_back(std::sqrt(1.f - a));
    };
    const float span = nm_hi - nm_lo;
    for (std::size_t i = 0; i < n; ++i) {
        direction(p.vx, p.vy, p.vz);
        direction(p.lx, p.ly, p.lz);
        const float first = nm_lo + span * u(rng);  // hero wavelengths: equally spaced, wrapped
        for (int k = 0; k < 4; ++k) p.hero.push_back(first + span * float(k) / 4.f > nm_hi ? first + span * float(k) / 4.f - span
                                                                                              : first + span * float(k) / 4.f);
    }
    return p;
}

template <class Body>
double ns_per_pair(double seconds, Body body) {
    std::size_t pairs = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (;;) {
        body();
        pairs += kBatch * kBatches;
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (s >= seconds) return s / double(pairs) * 1e9;
    }
}

// values: channel-major batches of kBatch pairs (value k of pair i of batch b at b * count + k * kBatch + i).
void report_precision(const Pairs& p, std::size_t count, const std::vector<float>& doubles, const std::vector<float>& floats) {
    npf::BrdfComparison comparison(count);
    double worst = 0.0;
    std::vector<float> d(count), f(count);
    for (std::size_t i = 0; i < p.vx.size(); ++i) {
        const std::size_t b = i / kBatch * kBatch, j = i % kBatch;
        for (std::size_t k = 0; k < count; ++k) {
            d[k] = doubles[b * count + k * kBatch + j], f[k] = floats[b * count + k * kBatch + j];
            if (d[k] > 0.f) worst = std::max(worst, std::fabs(double(f[k]) - double(d[k])) / double(d[k]));
        }
        comparison.add({p.vx[i], p.vy[i], p.vz[i]}, {p.lx[i], p.ly[i], p.lz[i]}, f.data(), d.data());
    }
    const npf::BrdfComparisonResult r = comparison.result();
    std::printf("float lanes against double: BRDF-space relative RMS %.3g at %zu pairs within 80 deg (budget 1e-4); "
                "largest relative difference of one value %.3g\n",
                r.relative_rms, r.used, worst);
}

}  // namespace

int main(int argc, char** argv) try {
    if (argc < 2 || argv[1][0] == '-') {
        std::fprintf(stderr, "usage: npf_bench_batch_floor FACTORS.exr [--seconds S] [--profile-float ROUNDS]\n");
        return 2;
    }
    double seconds = 1.0;
    int profile_rounds = 0;
    for (int i = 2; i < argc; i += 2) {
        const bool is_seconds = std::strcmp(argv[i], "--seconds") == 0, is_profile = std::strcmp(argv[i], "--profile-float") == 0;
        char* end = nullptr;
        const double v = i + 1 < argc ? std::strtod(argv[i + 1], &end) : 0.0;
        const bool number = end && end != argv[i + 1] && *end == '\0' && std::isfinite(v) && v > 0.0;
        if (!(is_seconds || is_profile) || !number || (is_profile && (v != std::floor(v) || v > 1e6))) {
            std::fprintf(stderr, "npf_bench_batch_floor: %s %s: want --seconds S (S > 0) or --profile-float ROUNDS (a whole number > 0)\n",
                         argv[i], i + 1 < argc ? argv[i + 1] : "(missing)");
            return 2;
        }
        if (is_seconds) seconds = v;
        if (is_profile) profile_rounds = int(v);
    }
    const npf::NpfClosure closure(argv[1], npf::NpfClosure::Path::Memory);
    npf::NpfClosure float_closure(argv[1], npf::NpfClosure::Path::Memory);
    float_closure.set_batch_precision(npf::BatchPrecision::Float);
    const npf::NpfModel& m = closure.model();
    const bool rgb = m.channels.is_rgb();
    const float nm_lo = rgb ? 0.f : m.channels.wavelengths().front(), nm_hi = rgb ? 0.f : m.channels.wavelengths().back();
    const Pairs p = random_pairs(kBatch * kBatches, nm_lo, nm_hi);
    const npf::AngleNeeds needs = m.angle_needs();
    std::vector<float> values(kBatch * std::max<std::size_t>(m.channels.size(), 4)), pdf(kBatch);
    volatile double sink = 0.0;

    auto eval_pass = [&](const npf::NpfClosure& c, bool with_pdf) {
        for (std::size_t b = 0; b < p.vx.size(); b += kBatch) {
            const npf::DirectionArrays view{p.vx.data() + b, p.vy.data() + b, p.vz.data() + b};
            const npf::DirectionArrays light{p.lx.data() + b, p.ly.data() + b, p.lz.data() + b};
            const npf::BatchWavelengths wl =
                rgb ? npf::BatchWavelengths::stored() : npf::BatchWavelengths::each_pair(p.hero.data() + 4 * b, 4);
            c.eval_batch(kBatch, view, light, wl, values.data(), with_pdf ? pdf.data() : nullptr);
            sink = sink + values[7];
        }
    };
    auto eval = [&](const npf::NpfClosure& c, bool with_pdf) { return ns_per_pair(seconds, [&] { eval_pass(c, with_pdf); }); };
    if (profile_rounds > 0) {
        for (int r = 0; r < profile_rounds; ++r) eval_pass(float_closure, true);
        std::printf("%s: %d x %zu pairs through eval_batch in float lanes with the pdf\n", argv[1], profile_rounds, p.vx.size());
        return 0;
    }

    npf::batch_detail::BlockAngles angles;
    npf::batch_detail::BlockAnglesOf<float> float_angles;
    const bool avx2 = npf::simd_isa() == npf::SimdIsa::Avx2;  // the kernel eval_batch runs
    const double angles_ns = ns_per_pair(seconds, [&] {
        for (std::size_t b = 0; b < p.vx.size(); b += npf::batch_detail::kBlock) {
            const float* view[3] = {p.vx.data() + b, p.vy.data() + b, p.vz.data() + b};
            const float* light[3] = {p.lx.data() + b, p.ly.data() + b, p.lz.data() + b};
            if (avx2) {
                npf::batch_detail::angles_avx2(npf::batch_detail::kBlock, view, light, needs, angles);
            } else {
                npf::batch_detail::angles_portable(npf::batch_detail::kBlock, view, light, needs, angles);
            }
            sink = sink + angles.theta_d[3];
        }
    });
    const double float_angles_ns = ns_per_pair(seconds, [&] {
        for (std::size_t b = 0; b < p.vx.size(); b += npf::batch_detail::kBlock) {
            const float* view[3] = {p.vx.data() + b, p.vy.data() + b, p.vz.data() + b};
            const float* light[3] = {p.lx.data() + b, p.ly.data() + b, p.lz.data() + b};
            npf::batch_detail::angles_float_avx2(npf::batch_detail::kBlock, view, light, needs, float_angles);
            sink = sink + float_angles.theta_d[3];
        }
    });
    const double values_ns = eval(closure, false), with_pdf_ns = eval(closure, true);
    const double float_values_ns = eval(float_closure, false), float_with_pdf_ns = eval(float_closure, true);
    std::printf("%s: %s, %s, angle needs: D azimuth %d, G azimuth %d, detail %d\n", argv[1], rgb ? "RGB" : "spectral", npf::simd_isa_name(npf::simd_isa()),
                needs.d_azimuth, needs.g_azimuth, needs.detail);
    std::printf("per pair, one thread, same run: angle kernel alone %.1f ns; eval_batch values %.1f ns; with pdf %.1f ns\n",
                angles_ns, values_ns, with_pdf_ns);
    std::printf("float lanes:                    angle kernel alone %.1f ns; eval_batch values %.1f ns; with pdf %.1f ns%s\n",
                float_angles_ns, float_values_ns, float_with_pdf_ns, avx2 ? "" : " (no AVX2: the double path)");
    // Every pair's values at both precisions.
    const std::size_t count = rgb ? m.channels.size() : 4;
    std::vector<float> doubles(p.vx.size() * count), floats(p.vx.size() * count);
    for (std::size_t b = 0; b < p.vx.size(); b += kBatch) {
        const npf::DirectionArrays view{p.vx.data() + b, p.vy.data() + b, p.vz.data() + b};
        const npf::DirectionArrays light{p.lx.data() + b, p.ly.data() + b, p.lz.data() + b};
        const npf::BatchWavelengths wl =
            rgb ? npf::BatchWavelengths::stored() : npf::BatchWavelengths::each_pair(p.hero.data() + 4 * b, 4);
        closure.eval_batch(kBatch, view, light, wl, doubles.data() + b * count, nullptr);
        float_closure.eval_batch(kBatch, view, light, wl, floats.data() + b * count, nullptr);
    }
    report_precision(p, count, doubles, floats);
    npf::render::RenderOptions options;
    options.width = options.height = 128;
    const auto lights = npf::render::directional_lights();
    using npf::testing::BatchedBrdf;
    const auto d = npf::render::render_directional(BatchedBrdf(argv[1], npf::BatchPrecision::Double), lights, options);
    const auto f = npf::render::render_directional(BatchedBrdf(argv[1], npf::BatchPrecision::Float), lights, options);
    std::printf("paired render (directional, 128 x 128) through the float lanes against the double path: %.1f dB (budget 80)\n",
                npf::render::compare_images(d.image, f.image).psnr);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "npf_bench_batch_floor: %s\n", e.what());
    return 1;
}
