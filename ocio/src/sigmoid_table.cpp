// The sigmoid coefficient table: fitted once when npf is built (make_sigmoid_table.cpp), then only read.
#include "sigmoid_fit.h"

#include <npf/core/error.h>
#include <npf/core/parallel.h>

#include <algorithm>
#include <string>
#include <utility>

namespace npf::color::detail {

namespace {

constexpr int kN = SigmoidTable::kResolution;
// Converged enough for a table whose interpolation error is ~1e-3: a Lab residual of 1e-4 is a
// colour error of about 1e-6.
constexpr double kTableTolerance = 1e-8;
constexpr int kTableIterations = 30;

double smoothstep(double x) { return x * x * (3.0 - 2.0 * x); }

}  // namespace

SigmoidTable::SigmoidTable() {
    for (int k = 0; k < kN; ++k) m_z[k] = smoothstep(smoothstep(k / double(kN - 1)));
}

SigmoidTable::SigmoidTable(std::vector<float> coefficients) : SigmoidTable() {
    if (coefficients.size() != kValues)
        throw Error("sigmoid table", std::to_string(coefficients.size()) + " coefficients, not " + std::to_string(kValues));
    m_coefficients = std::move(coefficients);
}

SigmoidTable SigmoidTable::fit() {
    SigmoidTable t;
    t.m_coefficients.assign(kValues, 0.f);
    // One task per (largest component, y node): each fits its x nodes along z. Tasks are
    // independent, and the table the same on any number of threads (at most 16).
    npf::parallel_for(std::size_t(3 * kN), [&](std::size_t task) {
        for (int xi = 0; xi < kN; ++xi) t.fit_column(int(task) / kN, int(task) % kN, xi);
    }, std::min(npf::thread_count(0), 16));
    return t;
}

std::size_t SigmoidTable::index(int largest, int zi, int yi, int xi) const {
    return ((((std::size_t(largest) * kN + zi) * kN + yi) * kN) + xi) * 3;
}

// pbrt-v4's order: start at a moderate brightness from zero coefficients and walk up, then down,
// each fit starting from its neighbour's solution (the solutions change smoothly with z).
void SigmoidTable::fit_column(int largest, int yi, int xi) {
    const double x = xi / double(kN - 1), y = yi / double(kN - 1);
    const int start = kN / 5;
    auto fit_node = [&](int zi, SigmoidCoefficients& c) {
        const double z = m_z[zi];
        Rgb rgb{};
        rgb[largest] = z;
        rgb[(largest + 1) % 3] = x * z;
        rgb[(largest + 2) % 3] = y * z;
        fit_sigmoid(rgb, c, Quadrature::Coarse, kTableTolerance, kTableIterations);
        const std::size_t at = index(largest, zi, yi, xi);
        for (int k = 0; k < 3; ++k) m_coefficients[at + k] = static_cast<float>(c[k]);
    };
    SigmoidCoefficients c{0.0, 0.0, 0.0};
    for (int zi = start; zi < kN; ++zi) fit_node(zi, c);
    c = {0.0, 0.0, 0.0};
    for (int zi = start; zi >= 0; --zi) fit_node(zi, c);
}

SigmoidCoefficients SigmoidTable::lookup(const Rgb& rgb) const {
    const int largest = rgb[0] > rgb[1] ? (rgb[0] > rgb[2] ? 0 : 2) : (rgb[1] > rgb[2] ? 1 : 2);
    const double z = rgb[largest];
    const double x = rgb[(largest + 1) % 3] * (kN - 1) / z, y = rgb[(largest + 2) % 3] * (kN - 1) / z;
    const int xi = std::min(static_cast<int>(x), kN - 2), yi = std::min(static_cast<int>(y), kN - 2);
    const int zi = std::clamp(static_cast<int>(std::upper_bound(m_z.begin(), m_z.end(), z) - m_z.begin()) - 1, 0, kN - 2);
    const double dx = x - xi, dy = y - yi, dz = (z - m_z[zi]) / (m_z[zi + 1] - m_z[zi]);
    SigmoidCoefficients c{};
    for (int k = 0; k < 3; ++k) {
        auto at = [&](int ox, int oy, int oz) { return double(m_coefficients[index(largest, zi + oz, yi + oy, xi + ox) + k]); };
        auto lerp = [](double t, double a, double b) { return a + t * (b - a); };
        c[k] = lerp(dz, lerp(dy, lerp(dx, at(0, 0, 0), at(1, 0, 0)), lerp(dx, at(0, 1, 0), at(1, 1, 0))),
                    lerp(dy, lerp(dx, at(0, 0, 1), at(1, 0, 1)), lerp(dx, at(0, 1, 1), at(1, 1, 1))));
    }
    return c;
}

}  // namespace npf::color::detail
