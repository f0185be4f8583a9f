// The batched closure (npf_batch.h): blocks of kBlock pairs; the angles of a block by a vector
// kernel (batch_angles.h), then the table lookups and values four pairs at a time by vector code
// (batch_values.h, AVX2), or eight at a time in float lanes (BatchPrecision::Float), or pair by
// pair with the scalar closure's code; sample's draws likewise (batch_draw.h).
#include <npf/shading/npf_batch.h>
#include <npf/shading/npf_closure.h>

#include "batch_angles.h"
#include "batch_draw.h"
#include "batch_pdf.h"
#include "batch_values.h"
#include "finite_float.h"

#include <npf/core/simd_isa.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace npf {

namespace {

using batch_detail::kBlock;

// Pair i of the arrays, for the domain check shared with the scalar closure (pair_in_domain).
bool in_domain(const DirectionArrays& view, const DirectionArrays& light, std::size_t i) {
    return pair_in_domain(Vec3(view.x[i], view.y[i], view.z[i]), Vec3(light.x[i], light.y[i], light.z[i]));
}

// The direction arrays of block [b, b + kBlock) as the kernels take them.
struct BlockPointers {
    const float* view[3];
    const float* light[3];
    BlockPointers(const DirectionArrays& v, const DirectionArrays& l, std::size_t b)
        : view{v.x + b, v.y + b, v.z + b}, light{l.x + b, l.y + b, l.z + b} {}
};

}  // namespace

namespace batch_detail {

std::vector<float> paired_cells_of(const float* tables, int count, int rows, int cols, bool pair_rows) {
    if (count < 1 || count > 4 || rows < 1 || cols < 1) return {};
    const std::size_t cells = std::size_t(rows) * std::size_t(cols);
    const std::size_t r_count = std::size_t(rows) + (pair_rows ? 1 : 0), c_count = std::size_t(cols) + (pair_rows ? 0 : 1);
    std::vector<float> out(r_count * c_count * 4, 0.f);
    for (std::size_t r = 0; r < r_count; ++r) {
        for (std::size_t c = 0; c < c_count; ++c) {
            const std::size_t from = std::min(r, std::size_t(rows) - 1) * std::size_t(cols) + c % std::size_t(cols);
            for (int k = 0; k < count; ++k) out[(r * c_count + c) * 4 + std::size_t(k)] = tables[std::size_t(k) * cells + from];
        }
    }
    return out;
}

std::vector<float> paired_cells_of(const SpectralBasis& s, int rows, int cols, bool pair_rows) {
    if (rows < 1 || cols < 1 || s.cells != std::size_t(rows) * std::size_t(cols)) return {};
    return paired_cells_of(s.basis.data(), s.rank, rows, cols, pair_rows);
}

std::size_t padded_detail_cell_count(const DetailGrid& grid) {
    if (grid.empty()) return 0;
    return (std::size_t(grid.theta_h) + 1) * (std::size_t(grid.theta_d) + 1) * (std::size_t(grid.phi_d) + 1);
}

std::vector<float> padded_detail_cells_of(const float* tables, int count, const DetailGrid& grid) {
    if (count < 1 || count > 4 || grid.empty()) return {};
    const std::size_t cells = grid.cells();
    std::vector<float> out(padded_detail_cell_count(grid) * 4, 0.f);
    std::size_t to = 0;
    for (int h = 0; h <= grid.theta_h; ++h) {
        for (int d = 0; d <= grid.theta_d; ++d) {
            for (int p = 0; p <= grid.phi_d; ++p, to += 4) {
                const std::size_t from = grid.index(std::min(h, grid.theta_h - 1), std::min(d, grid.theta_d - 1), p % grid.phi_d);
                for (int k = 0; k < count; ++k) out[to + std::size_t(k)] = tables[std::size_t(k) * cells + from];
            }
        }
    }
    return out;
}

std::vector<float> padded_detail_cells_of(const SpectralBasis& s, const DetailGrid& grid) {
    if (s.cells != grid.cells() || s.basis.size() < std::size_t(std::max(s.rank, 0)) * s.cells) return {};
    return padded_detail_cells_of(s.basis.data(), s.rank, grid);
}

SpectralBasis channel_tables_of(const SpectralBasis& s, std::size_t channels) {
    SpectralBasis out;
    if (s.rank < 1 || channels < 1 || channels > 4) return out;
    const std::size_t rank = std::size_t(s.rank);
    out.rank = int(channels);
    out.cells = s.cells;
    out.basis.assign(channels * s.cells, 0.f);
    out.weights.assign(channels * channels, 0.f);
    for (std::size_t c = 0; c < channels; ++c) {
        out.weights[c * channels + c] = 1.f;
        for (std::size_t cell = 0; cell < s.cells; ++cell) {
            double v = 0.0;
            for (std::size_t k = 0; k < rank; ++k) v += double(s.weights[c * rank + k]) * double(s.basis[k * s.cells + cell]);
            out.basis[c * s.cells + cell] = float(v);
        }
    }
    return out;
}

std::vector<float> channel_records_of(const NpfModel& m) {
    const std::size_t rd = std::size_t(m.D.rank), rg = std::size_t(m.G.rank), rr = std::size_t(m.detail.rank);
    if (2 + rd + rg + rr > 8) return {};
    const std::size_t channels = m.channel_count();
    std::vector<float> out(channels * 8, 0.f);
    for (std::size_t c = 0; c < channels; ++c) {
        float* r = out.data() + c * 8;
        r[0] = m.rho_d[c], r[1] = m.rho_s[c];
        for (std::size_t k = 0; k < rd; ++k) r[2 + k] = m.D.weights[c * rd + k];
        for (std::size_t k = 0; k < rg; ++k) r[2 + rd + k] = m.G.weights[c * rg + k];
        for (std::size_t k = 0; k < rr; ++k) r[2 + rd + rg + k] = m.detail.weights[c * rr + k];
    }
    return out;
}

}  // namespace batch_detail

void NpfClosure::eval_batch(std::size_t n, const DirectionArrays& view, const DirectionArrays& light,
                            BatchWavelengths wavelengths, float* values, float* pdf) const {
    const std::size_t count = value_count(wavelengths);
    const bool stored = !wavelengths.nm || m_model.channels.is_rgb();
    auto request_of = [&](std::size_t i) {
        if (stored) return WavelengthRequest::stored();
        return WavelengthRequest::at(wavelengths.nm + (wavelengths.per_pair ? i * count : 0), wavelengths.count);
    };
    auto zero = [&](std::size_t i) {
        for (std::size_t k = 0; k < count; ++k) values[k * n + i] = 0.f;
        if (pdf) pdf[i] = 0.f;
    };
    if (m_texture) {  // the TextureSystem's lookups are per pair
        for (std::size_t i = 0; i < n; ++i) {
            NpfModel::Lookup at;
            const Vec3 v(view.x[i], view.y[i], view.z[i]), l(light.x[i], light.y[i], light.z[i]);
            if (!lookup(v, l, at)) {
                zero(i);
                continue;
            }
            write_values(at, at.cos_o, request_of(i), values + i, n);
            if (pdf) pdf[i] = pdf_at(at.theta_h, at.u_h, at.phi_h, at.cos_d, at.cos_o);
        }
        return;
    }
    const bool avx2 = simd_isa() == SimdIsa::Avx2;
    const bool vector_values = avx2 && batch_detail::vector_values_apply(m_model);
    const bool float_lanes = vector_values && m_batch_precision == BatchPrecision::Float && cpu_has_fma() &&
                             batch_detail::float_values_apply(m_model);
    const batch_detail::ValueRequestOfBlock block_request{stored, wavelengths, &m_wavelengths, count};
    auto data_or_null = [](const std::vector<float>& v) { return v.empty() ? nullptr : v.data(); };
    const batch_detail::CellMajorBases cell_major{data_or_null(m_cell_major_d), data_or_null(m_cell_major_g),
                                                  data_or_null(m_cell_major_detail), data_or_null(m_cell_major_f),
                                                  data_or_null(m_channel_records), data_or_null(m_channel_d),
                                                  data_or_null(m_channel_g), data_or_null(m_channel_detail)};
    const AngleNeeds needs = m_model.angle_needs();
    batch_detail::BlockAngles angles;
    batch_detail::BlockAnglesOf<float> float_angles;
    std::uint8_t valid[kBlock];
    NpfModel::Lookup at;
    for (std::size_t b = 0; b < n; b += kBlock) {
        const std::size_t m = std::min(kBlock, n - b);
        const BlockPointers p(view, light, b);
        for (std::size_t j = avx2 ? batch_detail::domains_avx2(m, p.view, p.light, valid) : 0; j < m; ++j)
            valid[j] = in_domain(view, light, b + j);
        std::size_t done = 0, pdf_done = 0;
        if (float_lanes) {
            // Eight pairs at a time in float; the rest of the block (fewer than eight) in double.
            const std::size_t angled = batch_detail::angles_float_avx2(m, p.view, p.light, needs, float_angles);
            done = batch_detail::values_float_avx2(m_model, cell_major, float_angles, angled, valid, block_request, b, values, n);
            if (done < m) batch_detail::angles_portable(m - done, p.view, p.light, needs, angles, done);
            if (pdf) {
                pdf_done = batch_detail::pdfs_float_avx2(m_sampler, m_diffuse_probability, done, float_angles.theta_h,
                                                         float_angles.u_h, float_angles.phi_h, float_angles.cos_d,
                                                         float_angles.cos_o, valid, pdf + b);
            }
        } else {
            if (avx2) {
                batch_detail::angles_avx2(m, p.view, p.light, needs, angles);
            } else {
                batch_detail::angles_portable(m, p.view, p.light, needs, angles);
            }
            // The values of whole groups of four pairs by vector code, the rest pair by pair.
            if (vector_values) done = batch_detail::values_avx2(m_model, cell_major, angles, m, valid, block_request, b, values, n);
            if (pdf && avx2) {
                pdf_done = batch_detail::pdfs_avx2(m_sampler, m_diffuse_probability, m, angles.theta_h, angles.u_h, angles.phi_h,
                                                   angles.cos_d, angles.cos_o, valid, pdf + b);
            }
        }
        // The vector kernels wrote 0 for pairs outside the domain; the rest of the block pair by pair.
        const std::size_t float_done = float_lanes ? done : 0;  // pairs whose angles are float_angles'
        for (std::size_t j = pdf ? std::min(done, pdf_done) : done; j < m; ++j) {
            const std::size_t i = b + j;
            if (!valid[j]) {
                zero(i);
                continue;
            }
            if (j >= done) {
                m_model.position(angles.at(j), at);
                write_values(at, at.cos_o, request_of(i), values + i, n);
            }
            if (!pdf || j < pdf_done) continue;
            const batch_detail::BlockAnglesOf<float>& f = float_angles;
            pdf[i] = j < float_done ? pdf_at(f.theta_h[j], f.u_h[j], f.phi_h[j], f.cos_d[j], f.cos_o[j])
                                    : pdf_at(angles.theta_h[j], angles.u_h[j], angles.phi_h[j], angles.cos_d[j], angles.cos_o[j]);
        }
    }
}

void NpfClosure::pdf_batch(std::size_t n, const DirectionArrays& view, const DirectionArrays& light, float* pdf) const {
    const bool avx2 = simd_isa() == SimdIsa::Avx2;
    const bool d_azimuth = m_model.d_phi > 1;
    batch_detail::BlockHalfVectors h;
    for (std::size_t b = 0; b < n; b += kBlock) {
        const std::size_t m = std::min(kBlock, n - b);
        const BlockPointers p(view, light, b);
        if (avx2) {
            batch_detail::half_vectors_avx2(m, p.view, p.light, d_azimuth, h);
        } else {
            batch_detail::half_vectors_portable(m, p.view, p.light, d_azimuth, h);
        }
        std::size_t done = 0;
        if (avx2) {
            double cos_light[kBlock];
            for (std::size_t j = 0; j < m; ++j) cos_light[j] = light.z[b + j];
            done = batch_detail::pdfs_avx2(m_sampler, m_diffuse_probability, m, h.theta_h, h.u_h, h.phi_h, h.cos_d, cos_light,
                                           nullptr, pdf + b);
        }
        for (std::size_t j = 0; j < m; ++j) {
            const std::size_t i = b + j;
            if (!in_domain(view, light, i)) {
                pdf[i] = 0.f;
            } else if (j >= done) {
                pdf[i] = pdf_at(h.theta_h[j], h.u_h[j], h.phi_h[j], h.cos_d[j], light.z[i]);
            }
        }
    }
}

void NpfClosure::sample_batch(std::size_t n, const DirectionArrays& view, const float* u1, const float* u2,
                              BatchWavelengths wavelengths, float* const light_out[3], float* pdf, float* weights) const {
    // The draws (the half-vector strategy four pairs at a time by vector code, the cosine
    // strategy and the rest pair by pair), then the pdf and the values of the drawn pairs by the
    // batched code: the same numbers as sample(), whose pdf is pdf() and whose weights are eval's
    // values over that pdf.
    const bool vector_draw = simd_isa() == SimdIsa::Avx2 && !m_sampler.empty();
    std::uint8_t redo[kBlock];
    for (std::size_t b = 0; b < n; b += kBlock) {
        const std::size_t m = std::min(kBlock, n - b);
        const float* const v[3] = {view.x + b, view.y + b, view.z + b};
        float* const out[3] = {light_out[0] + b, light_out[1] + b, light_out[2] + b};
        const std::size_t done =
            vector_draw ? batch_detail::draw_lights_avx2(m_sampler, m_diffuse_probability, m, v, u1 + b, u2 + b, out, redo) : 0;
        for (std::size_t j = 0; j < m; ++j) {
            if (j < done && !redo[j]) continue;
            const std::size_t i = b + j;
            Vec3 light(0.f, 0.f, 0.f);
            if (!draw_light(Vec3(view.x[i], view.y[i], view.z[i]), u1[i], u2[i], light)) light = Vec3(0.f, 0.f, 0.f);
            light_out[0][i] = light.x;
            light_out[1][i] = light.y;
            light_out[2][i] = light.z;
        }
    }
    const DirectionArrays drawn{light_out[0], light_out[1], light_out[2]};
    if (!weights) {
        pdf_batch(n, view, drawn, pdf);
    } else {
        eval_batch(n, view, drawn, wavelengths, weights, pdf);
    }
    const std::size_t count = value_count(wavelengths);
    for (std::size_t i = 0; i < n; ++i) {
        if (pdf[i] > 0.f) {
            if (!weights) continue;
            const double inv_pdf = 1.0 / double(pdf[i]);
            for (std::size_t k = 0; k < count; ++k) weights[k * n + i] = finite_float(weights[k * n + i] * inv_pdf);
            continue;
        }
        pdf[i] = 0.f;
        light_out[0][i] = light_out[1][i] = light_out[2][i] = 0.f;
        if (weights) {
            for (std::size_t k = 0; k < count; ++k) weights[k * n + i] = 0.f;
        }
    }
}

}  // namespace npf
