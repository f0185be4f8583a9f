// npf bench MATERIAL.exr: what shading with a converted material costs, per call, on this
// machine: the closure's eval on both paths (4 hero wavelengths and the full stored spectrum),
// its importance sampling and pdf, and, with --against, the raw evaluation of the source file
// (the measured reader) at the same wavelengths and directions, side by side.
#include "command_line.h"
#include "commands.h"

#include <npf/materials/open_material.h>
#include <npf/core/error.h>
#include <npf/core/json_text.h>
#include <npf/core/input_file.h>
#include <npf/core/parallel.h>
#include <npf/core/simd_isa.h>
#include <npf/shading/npf_closure.h>
#include <npf/shading/npf_texture_file.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace npf::cli {

namespace {

const std::vector<FlagSpec> kFlags = {
    {"--against", true, "also time the raw evaluation of this material file (e.g. the .bsdf it was converted from)"},
    {"--json", false, "print one JSON object instead of the table"},
    {"--seconds", true, "time each measurement for at least this long (default 0.5)"},
    {"--threads", true, "also measure the memory-path eval throughput with this many threads (default: the cores)"},
    {"--help", false, "show this help"},
};

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
constexpr int kHeroSets = 64;   // wavelength quadruples, cycled
constexpr int kJsonDigits = 4;  // timings vary by more than that from run to run

struct Inputs {
    std::vector<Vec3> wo, wi;
    std::vector<float> u1, u2;
    std::vector<std::array<float, 4>> hero;  // empty for RGB materials
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
        // Hero wavelengths as a spectral renderer draws them: one at random, three more evenly
        // rotated through the stored range.
        const float lo = channels.wavelengths().front(), hi = channels.wavelengths().back(), span = hi - lo;
        for (int i = 0; i < kHeroSets; ++i) {
            const float first = uni(rng);
            std::array<float, 4> h;
            for (int k = 0; k < 4; ++k) h[std::size_t(k)] = lo + span * std::fmod(first + 0.25f * float(k), 1.f);
            in.hero.push_back(h);
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

}  // namespace

int run_bench(const std::vector<std::string>& args) {
    CommandLine cl("bench", args, kFlags);
    if (cl.has("--help")) {
        std::printf("%s%s", kHelp, usage_lines(kFlags).c_str());
        return 0;
    }
    cl.expect_positional(1, 1, "one MATERIAL.exr");
    const std::string path = cl.positional()[0];
    require_regular_file(path, "an NPF texture (.exr)");
    if (!is_npf_texture(path)) throw Error(path, "not an NPF factor texture (convert it first: npf convert)");
    const double seconds = cl.number("--seconds", 0.5);
    if (!(seconds > 0.0) || seconds > 600.0) {
        throw Error("--seconds", "expected a number of seconds in (0, 600], got '" + cl.value("--seconds") + "'");
    }
    const int threads = int(cl.whole("--threads", 1, 256, std::uint64_t(npf::thread_count(0))));
    const bool json = cl.has("--json");

    const NpfClosure memory(path, NpfClosure::Path::Memory);
    const NpfClosure texture(path, NpfClosure::Path::Texture);
    NpfClosure memory_float(path, NpfClosure::Path::Memory);  // the batched eval in float lanes
    memory_float.set_batch_precision(BatchPrecision::Float);
    std::unique_ptr<Brdf> raw;
    std::vector<ChannelQuery> raw_queries;
    const Channels& channels = memory.channels();
    const Inputs in = make_inputs(channels);
    if (cl.has("--against")) {
        const std::string raw_path = cl.value("--against");
        raw = open_material(raw_path);
        if (raw->info().channels.is_rgb() != channels.is_rgb()) {
            throw Error(raw_path, std::string("holds ") + (raw->info().channels.is_rgb() ? "RGB" : "spectral") +
                                      " data, the NPF texture " + (channels.is_rgb() ? "RGB" : "spectral") +
                                      " data: they are not the same material");
        }
        if (channels.is_rgb()) {
            raw_queries.push_back(raw->query(Channels::rgb()));
        } else {
            for (const auto& h : in.hero) raw_queries.push_back(raw->query(Channels::spectral({h.begin(), h.end()})));
        }
    }

    auto hero_of = [&](int i) {
        return channels.is_rgb() ? WavelengthRequest::stored()
                                 : WavelengthRequest::at(in.hero[std::size_t(i % kHeroSets)].data(), 4);
    };
    auto eval_batch = [&](const NpfClosure& c, bool full) {
        return [&c, full, &in, &hero_of] {
            std::vector<float> v(std::max<std::size_t>(c.channel_count(), 4));
            double sum = 0.0;
            for (int i = 0; i < kPairs; ++i) {
                const WavelengthRequest r = full ? WavelengthRequest::stored() : hero_of(i);
                sum += c.eval(in.wo[std::size_t(i)], in.wi[std::size_t(i)], r, v.data()) + v[0];
            }
            return sum;
        };
    };

    // The same pairs and hero wavelengths as structure-of-arrays, for the batched calls.
    std::vector<float> vx, vy, vz, lx, ly, lz, batch_hero;
    for (int i = 0; i < kPairs; ++i) {
        const std::size_t k = std::size_t(i);
        vx.push_back(in.wo[k].x), vy.push_back(in.wo[k].y), vz.push_back(in.wo[k].z);
        lx.push_back(in.wi[k].x), ly.push_back(in.wi[k].y), lz.push_back(in.wi[k].z);
        if (!channels.is_rgb()) {
            const auto& h = in.hero[std::size_t(i % kHeroSets)];
            batch_hero.insert(batch_hero.end(), h.begin(), h.end());
        }
    }
    std::vector<float> batch_values(std::size_t(kBatch) * std::max<std::size_t>(memory.channel_count(), 4));
    std::vector<float> batch_pdf(std::size_t(kBatch), 0.f);
    std::vector<float> drawn_x(std::size_t(kBatch), 0.f), drawn_y(std::size_t(kBatch), 0.f), drawn_z(std::size_t(kBatch), 0.f);
    float* const drawn[3] = {drawn_x.data(), drawn_y.data(), drawn_z.data()};
    auto sample_batches = [&] {
        for (int b = 0; b < kPairs; b += kBatch) {
            const std::size_t o = std::size_t(b);
            const DirectionArrays view{vx.data() + o, vy.data() + o, vz.data() + o};
            memory.sample_batch(std::size_t(kBatch), view, in.u1.data() + o, in.u2.data() + o, BatchWavelengths::stored(),
                                drawn, batch_pdf.data(), nullptr);
        }
        return double(batch_pdf[0]);
    };
    auto batches = [&](bool eval, const NpfClosure& closure) {
        return [&, eval] {
            for (int b = 0; b < kPairs; b += kBatch) {
                const std::size_t o = std::size_t(b);
                const DirectionArrays view{vx.data() + o, vy.data() + o, vz.data() + o};
                const DirectionArrays light{lx.data() + o, ly.data() + o, lz.data() + o};
                if (eval) {
                    const BatchWavelengths wl = channels.is_rgb() ? BatchWavelengths::stored()
                                                                  : BatchWavelengths::each_pair(batch_hero.data() + 4 * o, 4);
                    closure.eval_batch(std::size_t(kBatch), view, light, wl, batch_values.data(), batch_pdf.data());
                } else {
                    closure.pdf_batch(std::size_t(kBatch), view, light, batch_pdf.data());
                }
            }
            return double(batch_pdf[0]) + double(batch_values[0]);
        };
    };

    struct Row {
        const char* key;
        const char* label;
        Timing t;
    };
    std::vector<Row> rows;
    rows.push_back({"eval_memory_ns", "eval, memory, 4 hero wavelengths", time_calls(seconds, eval_batch(memory, false))});
    rows.push_back({"eval_memory_full_ns", "eval, memory, every stored channel", time_calls(seconds, eval_batch(memory, true))});
    rows.push_back({"eval_texture_ns", "eval, TextureSystem, 4 hero wavelengths", time_calls(seconds, eval_batch(texture, false))});
    rows.push_back({"eval_texture_full_ns", "eval, TextureSystem, every stored channel", time_calls(seconds, eval_batch(texture, true))});
    rows.push_back({"sample_ns", "sample: direction and pdf", time_calls(seconds, [&] {
                        double sum = 0.0;
                        ClosureSample s;
                        for (int i = 0; i < kPairs; ++i) {
                            const std::size_t k = std::size_t(i);
                            if (memory.sample_direction(in.wo[k], in.u1[k], in.u2[k], s)) sum += s.pdf;
                        }
                        return sum;
                    })});
    rows.push_back({"sample_weighted_ns", "sample with weights, 4 hero wavelengths", time_calls(seconds, [&] {
                        double sum = 0.0;
                        ClosureSample s;
                        float w[256];
                        for (int i = 0; i < kPairs; ++i) {
                            const std::size_t k = std::size_t(i);
                            if (memory.sample(in.wo[k], in.u1[k], in.u2[k], hero_of(i), s, w)) sum += w[0];
                        }
                        return sum;
                    })});
    rows.push_back({"pdf_ns", "pdf", time_calls(seconds, [&] {
                        double sum = 0.0;
                        for (int i = 0; i < kPairs; ++i) sum += memory.pdf(in.wo[std::size_t(i)], in.wi[std::size_t(i)]);
                        return sum;
                    })});
    rows.push_back({"eval_batch_ns", "eval_batch (1024 pairs), 4 hero wavelengths", time_calls(seconds, batches(true, memory))});
    rows.push_back({"eval_batch_float_ns", "eval_batch, float lanes", time_calls(seconds, batches(true, memory_float))});
    rows.push_back({"pdf_batch_ns", "pdf_batch (1024 pairs)", time_calls(seconds, batches(false, memory))});
    rows.push_back({"sample_batch_ns", "sample_batch (1024 pairs): direction and pdf", time_calls(seconds, sample_batches)});
    if (raw) {
        rows.push_back({"eval_raw_ns", "raw source evaluation, same wavelengths", time_calls(seconds, [&] {
                            double sum = 0.0;
                            float v[4];
                            for (int i = 0; i < kPairs; ++i) {
                                const std::size_t k = std::size_t(i);
                                // npf::Brdf conditions on its wi: the closure's wo.
                                raw->eval_cos(in.wo[k], in.wi[k], raw_queries[k % raw_queries.size()], v);
                                sum += v[0];
                            }
                            return sum;
                        })});
    }

    // Throughput: the memory eval on `threads` threads at once.
    std::atomic<std::uint64_t> total_calls{0};
    const auto start = std::chrono::steady_clock::now();
    {
        const auto batch = eval_batch(memory, false);
        // One item per thread, each timed on its own.
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
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double throughput = double(total_calls.load()) / wall;

    auto find = [&](const char* key) -> const Timing* {
        for (const Row& r : rows) {
            if (std::string(r.key) == key) return &r.t;
        }
        return nullptr;
    };
    const Timing* raw_t = find("eval_raw_ns");
    auto speedup_of = [&](const char* key) { return raw_t ? raw_t->ns_per_call / find(key)->ns_per_call : 0.0; };
    const double speedup = speedup_of("eval_memory_ns");
    const NpfModel& m = memory.model();

    if (json) {
        std::string out = "{\"material\": " + json_string(path) + ", \"channels\": " + std::to_string(m.channel_count()) +
                          ", \"rgb\": " + (channels.is_rgb() ? "true" : "false") + ", \"d_rank\": " +
                          std::to_string(m.D.rank) + ", \"g_rank\": " + std::to_string(m.G.rank);
        for (const Row& r : rows) out += std::string(", \"") + r.key + "\": " + json_number(r.t.ns_per_call, kJsonDigits);
        if (!raw) out += ", \"eval_raw_ns\": null";
        out += ", \"speedup_memory_vs_raw\": " + (raw ? json_number(speedup, kJsonDigits) : std::string("null"));
        out += ", \"speedup_batch_vs_raw\": " + (raw ? json_number(speedup_of("eval_batch_ns"), kJsonDigits) : std::string("null"));
        out += ", \"speedup_batch_float_vs_raw\": " +
               (raw ? json_number(speedup_of("eval_batch_float_ns"), kJsonDigits) : std::string("null"));
        out += std::string(", \"batch_isa\": \"") + simd_isa_name(simd_isa()) + "\"";
        out += ", \"threads\": " + std::to_string(threads) + ", \"eval_memory_calls_per_s_threaded\": " +
               json_number(throughput, kJsonDigits) + "}\n";
        std::fputs(out.c_str(), stdout);
        return 0;
    }
    std::printf("npf bench %s: %s, %zu channels, D %d x %d rank %d, G %d x %d rank %d%s\n", path.c_str(),
                channels.is_rgb() ? "RGB" : "spectral", m.channel_count(), m.d_theta, m.d_phi, m.D.rank, m.g_theta,
                m.g_phi, m.G.rank, raw ? (", against " + cl.value("--against")).c_str() : "");
    std::printf("  %-44s %10s %12s %8s\n", "measurement (one thread)", "ns/call", "calls", "seconds");
    for (const Row& r : rows) {
        std::printf("  %-44s %10.1f %12llu %8.2f\n", r.label, r.t.ns_per_call, (unsigned long long)r.t.calls,
                    r.t.seconds);
    }
    std::printf("  batched calls ran with %s\n", simd_isa_name(simd_isa()));
    if (raw) {
        std::printf("  memory eval is %.1f times faster than the raw evaluation; eval_batch %.1f times, in float lanes %.1f times\n",
                    speedup, speedup_of("eval_batch_ns"), speedup_of("eval_batch_float_ns"));
    }
    std::printf("  memory eval on %d threads: %.3g calls/s (%.1f ns/call per thread)\n", threads, throughput,
                1e9 * threads / throughput);
    return 0;
}

}  // namespace npf::cli
