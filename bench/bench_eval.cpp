// Time per eval_cos call (one direction pair, all channels) on the real RGL files, and per
// pdf and sample call. Direction pairs are drawn once, up front, so the loop times only the
// material. Run: build/bench/npf_bench_eval [--benchmark_filter=...]
#include <npf/converter/rgl_brdf.h>

#include <benchmark/benchmark.h>

#include <cmath>
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
