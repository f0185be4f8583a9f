#include "material_arrays.h"

#include <npf/materials/open_material.h>
#include <npf/core/error.h>
#include <npf/core/parallel.h>
#include <npf/core/vec.h>
#include <npf/shading/npf_brdf.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace npf::python {

namespace {

// Pairs per chunk of work: the batched closure's favourite size (npf bench's batches), and the
// unit the threads share (fixed, so the thread count does not change any result).
constexpr std::size_t kChunk = 1024;

// Row i as a unit direction, or npf::Error naming it: zero length, a NaN or an infinite component
// (npf eval's reader refuses non-finite numbers before it normalises).
Vec3 direction_at(const double* rows, std::size_t i, const char* name) {
    Vec3 w;
    const double* r = rows + 3 * i;
    if (!std::isfinite(r[0]) || !std::isfinite(r[1]) || !std::isfinite(r[2]) || !unit_direction(r[0], r[1], r[2], w)) {
        throw Error(std::string(name) + "[" + std::to_string(i) + "]", "a direction of zero length or not finite");
    }
    return w;
}

// A uniform number as the samplers take it: float, in [0, 1) (a double just below 1 rounds to 1).
float unit_interval(double u) { return std::min(float(u), std::nextafter(1.f, 0.f)); }

// Runs body(begin, end) over [0, n) in chunks of kChunk on up to `threads` threads.
template <class Body>
void for_chunks(std::size_t n, int threads, Body body) {
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    parallel_for(chunks, [&](std::size_t c) { body(c * kChunk, std::min(n, (c + 1) * kChunk)); }, threads);
}

// The directions of pairs [begin, end) as the batched closure takes them (structure of arrays).
struct ChunkDirections {
    std::vector<float> x, y, z;
    std::vector<Vec3> w;
    ChunkDirections(const double* rows, std::size_t begin, std::size_t end, const char* name)
        : x(end - begin), y(end - begin), z(end - begin), w(end - begin) {
        // unit_direction's common case in a loop that runs as vector code (no branch, no throw):
        // the root of the sum of squares and a division per component, the same operations, so
        // the same floats; rows outside its range (or bad) go through unit_direction afterwards.
        bool all_common = true;
        for (std::size_t j = 0; j < w.size(); ++j) {
            const double* r = rows + 3 * (begin + j);
            const double squares = r[0] * r[0] + r[1] * r[1] + r[2] * r[2], l = std::sqrt(squares);
            all_common &= squares_need_no_hypot(squares);
            x[j] = float(r[0] / l), y[j] = float(r[1] / l), z[j] = float(r[2] / l);
        }
        for (std::size_t j = 0; j < w.size(); ++j) {
            if (!all_common) {
                w[j] = direction_at(rows, begin + j, name);
                x[j] = w[j].x, y[j] = w[j].y, z[j] = w[j].z;
            }
            w[j] = Vec3(x[j], y[j], z[j]);
        }
    }
    DirectionArrays arrays() const { return {x.data(), y.data(), z.data()}; }
};

BatchWavelengths batch_wavelengths(const ArrayWavelengths& w, std::size_t begin) {
    if (!w.nm) return BatchWavelengths::stored();
    if (!w.per_pair) return BatchWavelengths::shared(w.nm, int(w.count));
    return BatchWavelengths::each_pair(w.nm + begin * w.count, int(w.count));
}

// The query of pair i (npf eval's: negative values clamped to 0).
class Queries {
public:
    Queries(const Brdf& brdf, const ArrayWavelengths& w) : m_brdf(brdf), m_w(w) {
        if (!w.per_pair) m_shared = query_of(w.nm);
    }
    ChannelQuery at(std::size_t i) const { return m_w.per_pair ? query_of(m_w.nm + i * m_w.count) : m_shared; }

private:
    ChannelQuery query_of(const float* nm) const {
        ChannelQuery q = nm ? m_brdf.query(Channels::spectral(std::vector<float>(nm, nm + m_w.count))) : m_brdf.native_query();
        q.clamp_negative = true;
        return q;
    }
    const Brdf& m_brdf;
    const ArrayWavelengths& m_w;
    ChannelQuery m_shared;
};

}  // namespace

MaterialArrays::MaterialArrays(const std::string& path) : m_brdf(open_material(path)) {
    if (const auto* npf_brdf = dynamic_cast<const NpfBrdf*>(m_brdf.get())) {
        if (npf_brdf->closure().path() == NpfClosure::Path::Memory) m_closure = &npf_brdf->closure();
    }
}

std::size_t MaterialArrays::value_count(const ArrayWavelengths& wavelengths, std::size_t n) const {
    const BrdfInfo& info = m_brdf->info();
    if (!wavelengths.nm) return info.channels.size();
    if (info.channels.is_rgb()) throw Error(info.path, "holds RGB data; wavelengths need a spectral file");
    if (wavelengths.count == 0) throw Error("wavelengths", "none given");
    // Every wavelength of the call, so that every source answers a bad one alike (an error, not
    // the closure's 0 for one source and a reader's error for another).
    const std::size_t rows = wavelengths.per_pair ? n : 1;
    for (std::size_t i = 0; i < rows * wavelengths.count; ++i) {
        const float nm = wavelengths.nm[i];
        if (!std::isfinite(nm) || !(nm > 0.f)) {
            throw Error("wavelengths[" + std::to_string(i / wavelengths.count) + ", " + std::to_string(i % wavelengths.count) +
                            "]",
                        "not a positive number of nanometres: " + std::to_string(nm));
        }
    }
    return wavelengths.count;
}

void MaterialArrays::eval(std::size_t n, const double* wi, const double* wo, const ArrayWavelengths& wavelengths,
                          bool cos, double* out, int threads) const {
    const std::size_t count = value_count(wavelengths, n);
    // f_r = (f_r cos) / cos, as npf eval divides; below the horizon the value is 0 and stays 0.
    auto store = [&](std::size_t i, std::size_t k, float value, const Vec3& light) {
        out[i * count + k] = cos ? double(value) : light.z > 0.f ? double(value) / double(light.z) : 0.0;
    };
    if (m_closure) {
        for_chunks(n, threads, [&](std::size_t begin, std::size_t end) {
            const ChunkDirections view(wi, begin, end, "wi"), light(wo, begin, end, "wo");
            const std::size_t m = end - begin;
            std::vector<float> values(count * m);
            m_closure->eval_batch(m, view.arrays(), light.arrays(), batch_wavelengths(wavelengths, begin), values.data(), nullptr);
            for (std::size_t j = 0; j < m; ++j)
                for (std::size_t k = 0; k < count; ++k) store(begin + j, k, values[k * m + j], light.w[j]);
        });
        return;
    }
    const Queries queries(*m_brdf, wavelengths);
    for_chunks(n, threads, [&](std::size_t begin, std::size_t end) {
        std::vector<float> values(count);
        for (std::size_t i = begin; i < end; ++i) {
            const Vec3 a = direction_at(wi, i, "wi"), b = direction_at(wo, i, "wo");
            m_brdf->eval_cos(a, b, queries.at(i), values.data());
            for (std::size_t k = 0; k < count; ++k) store(i, k, values[k], b);
        }
    });
}

void MaterialArrays::pdf(std::size_t n, const double* wi, const double* wo, double* out, int threads) const {
    for_chunks(n, threads, [&](std::size_t begin, std::size_t end) {
        if (m_closure) {
            const ChunkDirections view(wi, begin, end, "wi"), light(wo, begin, end, "wo");
            std::vector<float> pdf(end - begin);
            m_closure->pdf_batch(end - begin, view.arrays(), light.arrays(), pdf.data());
            for (std::size_t j = 0; j < pdf.size(); ++j) out[begin + j] = pdf[j];
            return;
        }
        for (std::size_t i = begin; i < end; ++i) out[i] = m_brdf->pdf(direction_at(wi, i, "wi"), direction_at(wo, i, "wo"));
    });
}

void MaterialArrays::sample(std::size_t n, const double* wi, const double* u, const ArrayWavelengths& wavelengths,
                            double* wo_out, double* pdf_out, double* weight_out, int threads) const {
    const std::size_t count = value_count(wavelengths, n);
    if (m_closure) {
        for_chunks(n, threads, [&](std::size_t begin, std::size_t end) {
            const ChunkDirections view(wi, begin, end, "wi");
            const std::size_t m = end - begin;
            std::vector<float> u1(m), u2(m), lx(m), ly(m), lz(m), pdf(m), weights(count * m);
            for (std::size_t j = 0; j < m; ++j) {
                u1[j] = unit_interval(u[2 * (begin + j)]);
                u2[j] = unit_interval(u[2 * (begin + j) + 1]);
            }
            float* const light[3] = {lx.data(), ly.data(), lz.data()};
            m_closure->sample_batch(m, view.arrays(), u1.data(), u2.data(), batch_wavelengths(wavelengths, begin), light,
                                    pdf.data(), weights.data());
            for (std::size_t j = 0; j < m; ++j) {
                const std::size_t i = begin + j;
                wo_out[3 * i] = lx[j], wo_out[3 * i + 1] = ly[j], wo_out[3 * i + 2] = lz[j];
                pdf_out[i] = pdf[j];
                for (std::size_t k = 0; k < count; ++k) weight_out[i * count + k] = weights[k * m + j];
            }
        });
        return;
    }
    const Queries queries(*m_brdf, wavelengths);
    for_chunks(n, threads, [&](std::size_t begin, std::size_t end) {
        std::vector<float> weights(count);
        for (std::size_t i = begin; i < end; ++i) {
            BrdfSample s;
            std::fill(weights.begin(), weights.end(), 0.f);
            const bool ok = m_brdf->sample(direction_at(wi, i, "wi"), Vec2{unit_interval(u[2 * i]), unit_interval(u[2 * i + 1])},
                                           queries.at(i), s, weights.data());
            wo_out[3 * i] = ok ? s.wo.x : 0.0, wo_out[3 * i + 1] = ok ? s.wo.y : 0.0, wo_out[3 * i + 2] = ok ? s.wo.z : 0.0;
            pdf_out[i] = ok ? s.pdf : 0.0;
            for (std::size_t k = 0; k < count; ++k) weight_out[i * count + k] = ok ? weights[k] : 0.0;
        }
    });
}

}  // namespace npf::python
