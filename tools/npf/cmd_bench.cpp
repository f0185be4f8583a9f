// npf bench MATERIAL.exr: what shading with a converted material costs, per call, on this
// machine: the closure's eval on both paths (4 hero wavelengths and the full stored spectrum),
// its importance sampling and pdf, and, with --against, the raw evaluation of the source file
// (the measured reader) at the same wavelengths and directions, side by side.
#include "command_line.h"
#include "commands.h"

#include <npf/color/wavelength_sampling.h>
#include <npf/materials/open_material.h>
#include <npf/core/error.h>
#include <npf/core/json_text.h>
#include <npf/core/input_file.h>
#include <npf/core/parallel.h>
#include <npf/core/simd_isa.h>
#include <npf/shading/npf_closure.h>
#include <npf/shading/npf_texture_file.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = flag_table({
    "--against VALUE  also time the raw evaluation of this material file (e.g. the .bsdf it was converted from)",
    "--json  print one JSON object instead of the table",
    "--seconds VALUE  time each measurement for at least this long (default 0.5)",
    "--threads VALUE  also measure the memory-path eval throughput with this many threads (default: the cores)",
});

const char* kHelp =
    "usage: npf bench MATERIAL.exr [--against RAW] [--json] [--seconds S] [--threads N]\n\n"
    "Times, per call, on random directions over the hemisphere:\n"
    "  eval_memory_ns        closure eval, in-memory tables, 4 hero wavelengths (RGB: R, G, B)\n"
    "  eval_memory_full_ns   the same for every stored channel\n"
    "  eval_texture_ns       closure eval through OpenImageIO's TextureSystem, 4 hero wavelengths\n"
    "  eval_texture_full_ns  the same for every stored channel\n"
    "  sample_ns             importance sample: a direction and its pdf (paper sec. 3.5)\n"
    "  sample_weighted_ns    sample plus the weight f cos / pdf at 4 hero wavelengths\n"
    "  pdf_ns                pdf of a given pair\n"
    "  eval_batch_ns         eval_batch over batches of 1024 pairs, memory path, 4 hero wavelengths per pair\n"
    "                        (RGB: R, G, B), per pair (batch_isa: the instruction set it ran with)\n"
    "  eval_batch_float_ns   the same with BatchPrecision::Float (float lanes, within docs/shading.md's budget)\n"
    "  pdf_batch_ns          pdf_batch over batches of 1024 pairs, per pair\n"
    "  sample_batch_ns       sample_batch (direction and pdf, as sample_ns) over batches of 1024 pairs, per pair\n"
    "  eval_raw_ns           --against: the source file's own evaluation, same wavelengths\n"
    "Single-threaded; the throughput line runs the memory eval on several threads at once.\n\n";

constexpr int kPairs = 4096;    // direction pairs, cycled
constexpr int kBatch = 1024;    // pairs per batched call
constexpr int kHeroSets = 64;   // hero wavelength sets, cycled
constexpr int kJsonDigits = 4;  // timings vary by more than that from run to run

constexpr int kHero = color::kHeroWavelengthCount;

// Random direction pairs and sampler numbers, and for spectral materials hero wavelengths, drawn
// once so that the loops time only the calls; the pairs also as structure-of-arrays for the
// batched calls.
struct Inputs {
    std::vector<Vec3> wo, wi;
    std::vector<float> u1, u2;
    std::vector<std::array<float, kHero>> hero;  // empty for RGB materials
    std::vector<float> vx, vy, vz, lx, ly, lz;   // wo and wi by component
    std::vector<float> batch_hero;               // kHero wavelengths per pair, cycling through `hero`
};

Inputs make_inputs(const Channels& channels) {
    Inputs in;
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    auto hemisphere = [&] {
        const float z = std::max(uni(rng), 1e-3f), phi = 2.f * kPi * uni(rng), r = std::sqrt(1.f - z * z);
        return Vec3(r * std::cos(phi), r * std::sin(phi), z);
    };
    for (int i = 0; i < kPairs; ++i) {
        in.wo.push_back(hemisphere());
        in.wi.push_back(hemisphere());
        in.u1.push_back(uni(rng));
        in.u2.push_back(uni(rng));
    }
    if (!channels.is_rgb()) {
        // Hero wavelengths as npf's spectral rendering draws them (color/wavelength_sampling.h);
        // a closure holds its values constant outside its stored range.
        for (int i = 0; i < kHeroSets; ++i) {
            const color::HeroWavelengths drawn = color::sample_hero_wavelengths(uni(rng));
            std::array<float, kHero> h;
            for (std::size_t k = 0; k < h.size(); ++k) h[k] = float(drawn.lambda_nm[k]);
            in.hero.push_back(h);
        }
    }
    for (int i = 0; i < kPairs; ++i) {
        const std::size_t k = std::size_t(i);
        in.vx.push_back(in.wo[k].x), in.vy.push_back(in.wo[k].y), in.vz.push_back(in.wo[k].z);
        in.lx.push_back(in.wi[k].x), in.ly.push_back(in.wi[k].y), in.lz.push_back(in.wi[k].z);
        if (!channels.is_rgb()) {
            const auto& h = in.hero[std::size_t(i % kHeroSets)];
            in.batch_hero.insert(in.batch_hero.end(), h.begin(), h.end());
        }
    }
    return in;
}

struct Timing {
    double ns_per_call = 0.0;
    std::uint64_t calls = 0;
    double seconds = 0.0;
};

// Runs `batch` (which makes kPairs calls) until at least `seconds` have passed.
Timing time_calls(double seconds, const std::function<double()>& batch) {
    using clock = std::chrono::steady_clock;
    volatile double sink = batch();  // warm caches (and the TextureSystem's tiles)
    Timing t;
    const auto start = clock::now();
    double elapsed = 0.0;
    do {
        sink = sink + batch();
        t.calls += kPairs;
        elapsed = std::chrono::duration<double>(clock::now() - start).count();
    } while (elapsed < seconds);
    t.seconds = elapsed;
    t.ns_per_call = 1e9 * elapsed / double(t.calls);
    return t;
}

// A loop of kPairs calls; returns a sum of what they gave, so that no call is optimised away.
using CallLoop = std::function<double()>;

WavelengthRequest hero_request(const Inputs& in, int i) {
    return in.hero.empty() ? WavelengthRequest::stored()
                           : WavelengthRequest::at(in.hero[std::size_t(i % kHeroSets)].data(), kHero);
}

CallLoop eval_loop(const NpfClosure& c, const Inputs& in, bool full) {
    return [&c, &in, full] {
        std::vector<float> v(std::max<std::size_t>(c.channel_count(), 4));
        double sum = 0.0;
        for (int i = 0; i < kPairs; ++i) {
            const WavelengthRequest r = full ? WavelengthRequest::stored() : hero_request(in, i);
            sum += c.eval(in.wo[std::size_t(i)], in.wi[std::size_t(i)], r, v.data()) + v[0];
        }
        return sum;
    };
}

CallLoop sample_loop(const NpfClosure& c, const Inputs& in, bool weighted) {
    return [&c, &in, weighted] {
        double sum = 0.0;
        ClosureSample s;
        float w[256];
        for (int i = 0; i < kPairs; ++i) {
            const std::size_t k = std::size_t(i);
            if (!weighted) {
                if (c.sample_direction(in.wo[k], in.u1[k], in.u2[k], s)) sum += s.pdf;
            } else if (c.sample(in.wo[k], in.u1[k], in.u2[k], hero_request(in, i), s, w)) {
                sum += w[0];
            }
        }
        return sum;
    };
}

CallLoop pdf_loop(const NpfClosure& c, const Inputs& in) {
    return [&c, &in] {
        double sum = 0.0;
        for (int i = 0; i < kPairs; ++i) sum += c.pdf(in.wo[std::size_t(i)], in.wi[std::size_t(i)]);
        return sum;
    };
}

enum class BatchCall { Eval, Pdf, Sample };

// kPairs pairs in batches of kBatch; the output buffers are made once, outside the timing.
CallLoop batch_loop(const NpfClosure& c, const Inputs& in, BatchCall call) {
    std::vector<float> values(std::size_t(kBatch) * std::max<std::size_t>(c.channel_count(), 4));
    const std::size_t n = std::size_t(kBatch);
    std::vector<float> pdf(n, 0.f), x(n, 0.f), y(n, 0.f), z(n, 0.f);
    return [&c, &in, call, values, pdf, x, y, z]() mutable {
        float* const drawn[3] = {x.data(), y.data(), z.data()};
        for (int b = 0; b < kPairs; b += kBatch) {
            const std::size_t o = std::size_t(b);
            const DirectionArrays view{in.vx.data() + o, in.vy.data() + o, in.vz.data() + o};
            const DirectionArrays light{in.lx.data() + o, in.ly.data() + o, in.lz.data() + o};
            if (call == BatchCall::Eval) {
                const BatchWavelengths wl = in.hero.empty() ? BatchWavelengths::stored()
                                                            : BatchWavelengths::each_pair(in.batch_hero.data() + kHero * o, kHero);
                c.eval_batch(std::size_t(kBatch), view, light, wl, values.data(), pdf.data());
            } else if (call == BatchCall::Pdf) {
                c.pdf_batch(std::size_t(kBatch), view, light, pdf.data());
            } else {
                c.sample_batch(std::size_t(kBatch), view, in.u1.data() + o, in.u2.data() + o, BatchWavelengths::stored(),
                               drawn, pdf.data(), nullptr);
            }
        }
        return call == BatchCall::Sample ? double(pdf[0]) : double(pdf[0]) + double(values[0]);
    };
}

// --against: the source file's own evaluation (npf::Brdf conditions on its wi: the closure's wo)
// at the same wavelengths.
CallLoop raw_loop(const Brdf& raw, const Channels& channels, const Inputs& in) {
    std::vector<ChannelQuery> queries;
    if (channels.is_rgb()) {
        queries.push_back(raw.query(Channels::rgb()));
    } else {
        for (const auto& h : in.hero) queries.push_back(raw.query(Channels::spectral({h.begin(), h.end()})));
    }
    return [&raw, &in, queries] {
        double sum = 0.0;
        float v[kHero];
        for (int i = 0; i < kPairs; ++i) {
            const std::size_t k = std::size_t(i);
            raw.eval_cos(in.wo[k], in.wi[k], queries[k % queries.size()], v);
            sum += v[0];
        }
        return sum;
    };
}

std::unique_ptr<Brdf> open_raw(const std::string& raw_path, const Channels& channels) {
    std::unique_ptr<Brdf> raw = open_material(raw_path);
    if (raw->info().channels.is_rgb() != channels.is_rgb()) {
        throw Error(raw_path, std::string("holds ") + (raw->info().channels.is_rgb() ? "RGB" : "spectral") +
                                  " data, the NPF texture " + (channels.is_rgb() ? "RGB" : "spectral") +
                                  " data: they are not the same material");
    }
    return raw;
}

struct Row {
    const char* key;
    const char* label;
    Timing t;
};

// Every single-threaded measurement, in the order of the help and the report.
std::vector<Row> time_each_call(const std::string& path, const NpfClosure& memory, const Brdf* raw, const Inputs& in,
                                double seconds) {
    const NpfClosure texture(path, NpfClosure::Path::Texture);
    NpfClosure memory_float(path, NpfClosure::Path::Memory);  // the batched eval in float lanes
    memory_float.set_batch_precision(BatchPrecision::Float);
    std::vector<Row> rows = {
        {"eval_memory_ns", "eval, memory, 4 hero wavelengths", time_calls(seconds, eval_loop(memory, in, false))},
        {"eval_memory_full_ns", "eval, memory, every stored channel", time_calls(seconds, eval_loop(memory, in, true))},
        {"eval_texture_ns", "eval, TextureSystem, 4 hero wavelengths", time_calls(seconds, eval_loop(texture, in, false))},
        {"eval_texture_full_ns", "eval, TextureSystem, every stored channel", time_calls(seconds, eval_loop(texture, in, true))},
        {"sample_ns", "sample: direction and pdf", time_calls(seconds, sample_loop(memory, in, false))},
        {"sample_weighted_ns", "sample with weights, 4 hero wavelengths", time_calls(seconds, sample_loop(memory, in, true))},
        {"pdf_ns", "pdf", time_calls(seconds, pdf_loop(memory, in))},
        {"eval_batch_ns", "eval_batch (1024 pairs), 4 hero wavelengths", time_calls(seconds, batch_loop(memory, in, BatchCall::Eval))},
        {"eval_batch_float_ns", "eval_batch, float lanes", time_calls(seconds, batch_loop(memory_float, in, BatchCall::Eval))},
        {"pdf_batch_ns", "pdf_batch (1024 pairs)", time_calls(seconds, batch_loop(memory, in, BatchCall::Pdf))},
        {"sample_batch_ns", "sample_batch (1024 pairs): direction and pdf", time_calls(seconds, batch_loop(memory, in, BatchCall::Sample))},
    };
    if (raw) {
        rows.push_back({"eval_raw_ns", "raw source evaluation, same wavelengths",
                        time_calls(seconds, raw_loop(*raw, memory.channels(), in))});
    }
    return rows;
}

// Calls per second of the memory eval on `threads` threads at once, each timed on its own.
double threaded_throughput(const NpfClosure& memory, const Inputs& in, int threads, double seconds) {
    std::atomic<std::uint64_t> total_calls{0};
    const auto start = std::chrono::steady_clock::now();
    const CallLoop batch = eval_loop(memory, in, false);
    npf::parallel_for(std::size_t(threads), [&](std::size_t) {
        volatile double sink = 0.0;
        const auto t0 = std::chrono::steady_clock::now();
        std::uint64_t calls = 0;
        do {
            sink = sink + batch();
            calls += kPairs;
        } while (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < seconds);
        total_calls += calls;
    }, threads);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return double(total_calls.load()) / wall;
}

struct BenchReport {
    std::string path, raw_path;  // raw_path empty without --against
    std::vector<Row> rows;
    int threads = 0;
    double throughput = 0.0;

    const Timing* find(const char* key) const {
        for (const Row& r : rows) {
            if (std::string(r.key) == key) return &r.t;
        }
        return nullptr;
    }
    // How many times faster than the raw evaluation `key` is; 0 without --against.
    double speedup(const char* key) const {
        const Timing* raw = find("eval_raw_ns");
        return raw ? raw->ns_per_call / find(key)->ns_per_call : 0.0;
    }
};

std::string json_report(const BenchReport& b, const NpfClosure& memory) {
    const NpfModel& m = memory.model();
    const bool raw = !b.raw_path.empty();
    auto speedup = [&](const char* key) { return raw ? json_number(b.speedup(key), kJsonDigits) : std::string("null"); };
    std::string out = "{\"material\": " + json_string(b.path) + ", \"channels\": " + std::to_string(m.channel_count()) +
                      ", \"rgb\": " + (memory.channels().is_rgb() ? "true" : "false") + ", \"d_rank\": " +
                      std::to_string(m.D.rank) + ", \"g_rank\": " + std::to_string(m.G.rank);
    for (const Row& r : b.rows) out += std::string(", \"") + r.key + "\": " + json_number(r.t.ns_per_call, kJsonDigits);
    if (!raw) out += ", \"eval_raw_ns\": null";
    out += ", \"speedup_memory_vs_raw\": " + speedup("eval_memory_ns");
    out += ", \"speedup_batch_vs_raw\": " + speedup("eval_batch_ns");
    out += ", \"speedup_batch_float_vs_raw\": " + speedup("eval_batch_float_ns");
    out += std::string(", \"batch_isa\": \"") + simd_isa_name(simd_isa()) + "\"";
    out += ", \"threads\": " + std::to_string(b.threads) + ", \"eval_memory_calls_per_s_threaded\": " +
           json_number(b.throughput, kJsonDigits) + "}\n";
    return out;
}

void print_text(const BenchReport& b, const NpfClosure& memory) {
    const NpfModel& m = memory.model();
    const bool raw = !b.raw_path.empty();
    std::printf("npf bench %s: %s, %zu channels, D %d x %d rank %d, G %d x %d rank %d%s\n", b.path.c_str(),
                memory.channels().is_rgb() ? "RGB" : "spectral", m.channel_count(), m.d_theta, m.d_phi, m.D.rank,
                m.g_theta, m.g_phi, m.G.rank, raw ? (", against " + b.raw_path).c_str() : "");
    std::printf("  %-44s %10s %12s %8s\n", "measurement (one thread)", "ns/call", "calls", "seconds");
    for (const Row& r : b.rows) {
        std::printf("  %-44s %10.1f %12llu %8.2f\n", r.label, r.t.ns_per_call, (unsigned long long)r.t.calls,
                    r.t.seconds);
    }
    std::printf("  batched calls ran with %s\n", simd_isa_name(simd_isa()));
    if (raw) {
        std::printf("  memory eval is %.1f times faster than the raw evaluation; eval_batch %.1f times, in float lanes %.1f times\n",
                    b.speedup("eval_memory_ns"), b.speedup("eval_batch_ns"), b.speedup("eval_batch_float_ns"));
    }
    std::printf("  memory eval on %d threads: %.3g calls/s (%.1f ns/call per thread)\n", b.threads, b.throughput,
                1e9 * b.threads / b.throughput);
}

}  // namespace

int run_bench(const std::vector<std::string>& args) {
    const CommandLine cl = read_command_line(kHelp, kFlags, args);
    cl.expect_positional(1, 1, "one MATERIAL.exr");
    BenchReport report;
    report.path = cl.positional()[0];
    require_regular_file(report.path, "an NPF texture (.exr)");
    if (!is_npf_texture(report.path)) throw Error(report.path, "not an NPF factor texture (convert it first: npf convert)");
    const double seconds = cl.number("--seconds", 0.5);
    if (!(seconds > 0.0) || seconds > 600.0) {
        throw Error("--seconds", "expected a number of seconds in (0, 600], got '" + cl.value("--seconds") + "'");
    }
    report.threads = int(cl.whole("--threads", 1, 256, std::uint64_t(npf::thread_count(0))));

    const NpfClosure memory(report.path, NpfClosure::Path::Memory);
    const Inputs in = make_inputs(memory.channels());
    std::unique_ptr<Brdf> raw;
    if (cl.has("--against")) {
        report.raw_path = cl.value("--against");
        raw = open_raw(report.raw_path, memory.channels());
    }
    report.rows = time_each_call(report.path, memory, raw.get(), in, seconds);
    report.throughput = threaded_throughput(memory, in, report.threads, seconds);
    if (cl.has("--json")) {
        std::fputs(json_report(report, memory).c_str(), stdout);
    } else {
        print_text(report, memory);
    }
    return 0;
}

}  // namespace npf::cli
