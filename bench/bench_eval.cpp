// Time per eval_cos call (one direction pair, all channels) on the real RGL files, and per
// pdf and sample call. Direction pairs are drawn once, up front, so the loop times only the
// material. Run: build/bench/npf_bench_eval [--benchmark_filter=...]
#include <npf/color/wavelength_sampling.h>
#include <npf/materials/rgl_brdf.h>
#ifdef NPF_BENCH_SYNTHETIC
#include "synthetic_rgl.h"
#endif

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <cstdio>
#include <random>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace {

const char* kMaterials[] = {"acrylic_felt_green_rgb", "cg_sunflower_rgb", "ilm_l3_37_metallic_rgb",
                            "paper_white_rgb", "vch_golden_yellow_rgb"};

std::string material_path(const std::string& name) {
    const char* env = std::getenv("NPF_SHARED_DATA");
    return std::string(env ? env : NPF_SHARED_DATA_DIR) + "/rgl/" + name + ".bsdf";
}

struct Pairs {
    std::vector<npf::Vec3> wi, wo;
};

const Pairs& random_pairs() {
    static Pairs pairs = [] {
        Pairs p;
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        auto hemisphere = [&] {
            float z = u(rng), phi = 2.f * npf::kPi * u(rng), r = std::sqrt(std::fmax(0.f, 1.f - z * z));
            return npf::Vec3(r * std::cos(phi), r * std::sin(phi), z);
        };
        for (int i = 0; i < 4096; ++i) {
            p.wi.push_back(hemisphere());
            p.wo.push_back(hemisphere());
        }
        return p;
    }();
    return pairs;
}

void BM_EvalRgb(benchmark::State& state, const std::string& name) {
    auto brdf = npf::RglBrdf::load(material_path(name));
    npf::ChannelQuery q = brdf->native_query();
    const Pairs& p = random_pairs();
    float out[3];
    std::size_t i = 0;
    for (auto _ : state) {
        brdf->eval_cos(p.wi[i], p.wo[i], q, out);
        benchmark::DoNotOptimize(out);
        i = (i + 1) & 4095;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_Pdf(benchmark::State& state, const std::string& name) {
    auto brdf = npf::RglBrdf::load(material_path(name));
    const Pairs& p = random_pairs();
    std::size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(brdf->pdf(p.wi[i], p.wo[i]));
        i = (i + 1) & 4095;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_Sample(benchmark::State& state, const std::string& name) {
    auto brdf = npf::RglBrdf::load(material_path(name));
    npf::ChannelQuery q = brdf->native_query();
    const Pairs& p = random_pairs();
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<npf::Vec2> us(4096);
    for (auto& v : us) v = {u(rng), u(rng)};
    float weight[3];
    npf::BrdfSample s;
    std::size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(brdf->sample(p.wi[i], us[i], q, s, weight));
        i = (i + 1) & 4095;
    }
    state.SetItemsProcessed(state.iterations());
}

#ifdef NPF_BENCH_SYNTHETIC
// A 195-wavelength (360 to 1000 nm) anisotropic spectral file at the database's data grid:
// all wavelengths in one call (direction work shared) against one call per wavelength.
const npf::RglBrdf& spectral_material() {
    static std::unique_ptr<npf::RglBrdf> brdf = [] {
        npf::testing::SyntheticRglSpec spec;
        spec.phi_count = 9;
        spec.spectral = true;
        spec.wavelengths.clear();
        for (int i = 0; i < 195; ++i) spec.wavelengths.push_back(360.f + 640.f * float(i) / 194.f);
        spec.data_size = 32;
        spec.vndf_size = 128;
        spec.ndf_size = 128;
        spec.theta_count = 8;
        spec.alpha_x = 0.1f;
        spec.alpha_y = 0.3f;
        const std::string path = npf::testing::temporary_folder("bench") + "/aniso_spectral_195.bsdf";
        npf::testing::write_synthetic_rgl(spec, path);
        return npf::RglBrdf::load(path);
    }();
    return *brdf;
}

void BM_EvalSpectralAllAtOnce(benchmark::State& state) {
    const npf::RglBrdf& brdf = spectral_material();
    npf::ChannelQuery q = brdf.native_query();
    const Pairs& p = random_pairs();
    std::vector<float> out(q.size());
    std::size_t i = 0;
    for (auto _ : state) {
        brdf.eval_cos(p.wi[i], p.wo[i], q, out.data());
        benchmark::DoNotOptimize(out.data());
        i = (i + 1) & 4095;
    }
    state.SetItemsProcessed(state.iterations());
}

void BM_EvalSpectralOneCallPerWavelength(benchmark::State& state) {
    const npf::RglBrdf& brdf = spectral_material();
    std::vector<npf::ChannelQuery> queries;
    for (float lambda : brdf.info().channels.wavelengths()) queries.push_back(brdf.query(npf::Channels::spectral({lambda})));
    const Pairs& p = random_pairs();
    float out;
    std::size_t i = 0;
    for (auto _ : state) {
        for (const npf::ChannelQuery& q : queries) brdf.eval_cos(p.wi[i], p.wo[i], q, &out);
        benchmark::DoNotOptimize(out);
        i = (i + 1) & 4095;
    }
    state.SetItemsProcessed(state.iterations());
}

// One set of hero wavelengths as npf's spectral rendering draws them (color/wavelength_sampling.h),
// at a fixed sample: the same four wavelengths every run.
std::vector<float> hero_wavelengths() {
    const npf::color::HeroWavelengths hero = npf::color::sample_hero_wavelengths(0.3);
    return std::vector<float>(hero.lambda_nm.begin(), hero.lambda_nm.end());
}

void BM_EvalSpectralFourHeroWavelengths(benchmark::State& state) {
    const npf::RglBrdf& brdf = spectral_material();
    npf::ChannelQuery q = brdf.query(npf::Channels::spectral(hero_wavelengths()));
    const Pairs& p = random_pairs();
    float out[npf::color::kHeroWavelengthCount];
    std::size_t i = 0;
    for (auto _ : state) {
        brdf.eval_cos(p.wi[i], p.wo[i], q, out);
        benchmark::DoNotOptimize(out);
        i = (i + 1) & 4095;
    }
    state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_EvalSpectralAllAtOnce)->Name("eval_cos_spectral195/all_in_one_call");
BENCHMARK(BM_EvalSpectralOneCallPerWavelength)->Name("eval_cos_spectral195/one_call_per_wavelength");
BENCHMARK(BM_EvalSpectralFourHeroWavelengths)->Name("eval_cos_spectral195/four_hero_wavelengths");
#endif

int register_all() {
    for (const char* name : kMaterials) {
        struct stat st;
        if (::stat(material_path(name).c_str(), &st) != 0) {
            std::fprintf(stderr, "skipping %s: %s not found\n", name, material_path(name).c_str());
            continue;
        }
        benchmark::RegisterBenchmark((std::string("eval_cos_rgb/") + name).c_str(), BM_EvalRgb, std::string(name));
        benchmark::RegisterBenchmark((std::string("pdf/") + name).c_str(), BM_Pdf, std::string(name));
        benchmark::RegisterBenchmark((std::string("sample_rgb/") + name).c_str(), BM_Sample, std::string(name));
    }
    return 0;
}

const int registered = register_all();

}  // namespace

BENCHMARK_MAIN();
