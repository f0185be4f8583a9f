// npf_bench_batch_floor: what bounds the batched eval from below (issue 19's note, docs/shading.md).
//
//   build/bench/npf_bench_batch_floor FACTORS.exr [--seconds S]
//
// Two measurements on one factor texture, memory path, random pairs over the hemisphere (4 hero
// wavelengths per pair on a spectral file, R, G, B on an RGB one):
// 1. Time per pair of the batched angle kernel alone (the angles of every lookup, in double, as
//    eval_batch computes them), beside eval_batch without and with the pdf, in the same run: the
//    angles are a part no faster eval can skip.
// 2. The precision those angles need: every value of the model at pairs whose angles are rounded
//    to float after the exact double computation (half an ulp: less error than any float angle
//    kernel could have), against the values at the double angles. Where that moves values by
//    more than the batched closure's allowed 1e-6 relative, the angle kernel cannot run in float
//    (8 lanes) and keeps its 4 double lanes.
#include "batch_angles.h"

#include <npf/core/simd_isa.h>
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

void report_precision(const npf::NpfModel& m, const Pairs& p) {
    const npf::AngleNeeds needs = m.angle_needs();
    const std::size_t channels = m.channels.size();
    std::vector<double> exact(channels), rounded(channels);
    std::size_t over = 0, total = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < p.vx.size(); ++i) {
        npf::PairAngles a;
        npf::pair_angles(p.vx[i], p.vy[i], p.vz[i], p.lx[i], p.ly[i], p.lz[i], needs, a);
        npf::PairAngles f = a;
        for (double* x : {&f.cos_i, &f.cos_o, &f.inv_cos_product, &f.theta_h, &f.u_h, &f.phi_h, &f.cos_d, &f.theta_d,
                          &f.theta_gi, &f.phi_gi, &f.theta_go, &f.phi_go, &f.phi_d})
            *x = double(float(*x));
        npf::NpfModel::Lookup at_exact, at_rounded;
        m.position(a, at_exact);
        m.position(f, at_rounded);
        m.values(at_exact, exact.data());
        m.values(at_rounded, rounded.data());
        for (std::size_t c = 0; c < channels; ++c) {
            const double x = std::max(0.0, exact[c]), y = std::max(0.0, rounded[c]);
            if (!(x > 0.0)) continue;
            const double relative = std::fabs(y - x) / x;
            ++total;
            over += relative > 1e-6;
            worst = std::max(worst, relative);
        }
    }
    std::printf("angles rounded to float: %zu of %zu values (%.2f %%) move by more than 1e-6 relative, the worst by %.3g\n",
                over, total, 100.0 * double(over) / double(std::max<std::size_t>(total, 1)), worst);
}

}  // namespace

int main(int argc, char** argv) try {
    if (argc < 2 || argv[1][0] == '-') {
        std::fprintf(stderr, "usage: npf_bench_batch_floor FACTORS.exr [--seconds S]\n");
        return 2;
    }
    double seconds = 1.0;
    for (int i = 2; i + 1 < argc; i += 2)
        if (std::strcmp(argv[i], "--seconds") == 0) seconds = std::atof(argv[i + 1]);
    const npf::NpfClosure closure(argv[1], npf::NpfClosure::Path::Memory);
    const npf::NpfModel& m = closure.model();
    const bool rgb = m.channels.is_rgb();
    const float nm_lo = rgb ? 0.f : m.channels.wavelengths().front(), nm_hi = rgb ? 0.f : m.channels.wavelengths().back();
    const Pairs p = random_pairs(kBatch * kBatches, nm_lo, nm_hi);
    const npf::AngleNeeds needs = m.angle_needs();
    std::vector<float> values(kBatch * 4), pdf(kBatch);
    volatile double sink = 0.0;

    npf::batch_detail::BlockAngles angles;
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
    auto eval = [&](bool with_pdf) {
        return ns_per_pair(seconds, [&] {
            for (std::size_t b = 0; b < p.vx.size(); b += kBatch) {
                const npf::DirectionArrays view{p.vx.data() + b, p.vy.data() + b, p.vz.data() + b};
                const npf::DirectionArrays light{p.lx.data() + b, p.ly.data() + b, p.lz.data() + b};
                const npf::BatchWavelengths wl =
                    rgb ? npf::BatchWavelengths::stored() : npf::BatchWavelengths::each_pair(p.hero.data() + 4 * b, 4);
                closure.eval_batch(kBatch, view, light, wl, values.data(), with_pdf ? pdf.data() : nullptr);
                sink = sink + values[7];
            }
        });
    };
    const double values_ns = eval(false), with_pdf_ns = eval(true);
    std::printf("%s: %s, %s, angle needs: D azimuth %d, G azimuth %d, detail %d\n", argv[1], rgb ? "RGB" : "spectral", npf::simd_isa_name(npf::simd_isa()),
                needs.d_azimuth, needs.g_azimuth, needs.detail);
    std::printf("per pair, one thread, same run: angle kernel alone %.1f ns; eval_batch values %.1f ns; with pdf %.1f ns\n",
                angles_ns, values_ns, with_pdf_ns);
    report_precision(m, p);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "npf_bench_batch_floor: %s\n", e.what());
    return 1;
}
