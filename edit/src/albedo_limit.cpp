#include <npf/edit/albedo_limit.h>

#include "tables.h"

#include <npf/converter/convert.h>
#include <npf/core/error.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

namespace npf::edit {

namespace {

// A G table without azimuth under an anisotropic D: its one value per row serves every
// azimuth of the view, so the row's factor is the smallest over these many azimuths.
constexpr int kAzimuthsPerIsotropicRow = 8;

void set_metadata(NpfModel& m, const std::string& key, const std::string& value) {
    for (auto& kv : m.metadata) {
        if (kv.first == key) kv.second = value;
    }
}

bool has_metadata(const NpfModel& m, const std::string& key) {
    return std::any_of(m.metadata.begin(), m.metadata.end(), [&](const auto& kv) { return kv.first == key; });
}

}  // namespace

NpfModel limit_albedo(const NpfModel& model, const AlbedoLimit& limit, EditRecord* record) {
    if (!(limit.cap > 0.0 && limit.cap <= 1.0)) {
        throw Error("limit_albedo", "the cap must be in (0, 1], got " + detail::num(limit.cap));
    }
    if (!(limit.margin >= 0.0 && limit.margin < 0.1)) {
        throw Error("limit_albedo", "the margin must be in [0, 0.1), got " + detail::num(limit.margin));
    }
    if (limit.passes < 1 || limit.passes > 16) {
        throw Error("limit_albedo", "passes must be in 1..16, got " + std::to_string(limit.passes));
    }
    const double target = limit.cap * (1.0 - limit.margin);
    const std::size_t C = model.channel_count();
    NpfModel out = model;

    // Channels whose diffuse term alone reaches the cap leave no room for a specular term.
    int diffuse_capped = 0;
    for (std::size_t c = 0; c < C; ++c) {
        if (kPiD * out.rho_d[c] >= limit.cap) {
            out.rho_d[c] = float(target / kPiD);
            out.rho_s[c] = 0.f;
            ++diffuse_capped;
        }
    }

    AlbedoOptions quadrature;
    quadrature.u_cells = limit.u_cells;
    quadrature.phi_cells = limit.phi_cells;
    if (!out.isotropic() && limit.u_cells == 0) quadrature.u_cells = 64;
    if (!out.isotropic() && limit.phi_cells == 0) quadrature.phi_cells = 64;
    const int azimuths = out.g_phi == 1 && out.d_phi > 1 ? kAzimuthsPerIsotropicRow : 1;

    // Passes over the G cells: each measures the albedo at the cell centres of the current
    // model and lowers G where it exceeds the target. Lowering G also lowers other views' albedo
    // (G weighs the light side too), so when many cells exceed, one exact step per cell would
    // overshoot (a uniformly too bright material would end near cap^2): the passes before the
    // last take the square root of the needed factor, the last the whole factor. A cell below
    // the target never needs a later pass (its albedo only falls), so only cells lowered in the
    // previous pass are measured again. The last pass's exact step leaves every cell centre at
    // or below the target (see the header).
    const std::size_t cells = std::size_t(out.g_theta) * std::size_t(out.g_phi);
    std::vector<double> total(cells, 1.0), needed(cells, 1.0), albedo_max(cells, 0.0);
    auto measure = [&](std::size_t cell) {
        const int k = int(cell / std::size_t(out.g_phi)), j = int(cell % std::size_t(out.g_phi));
        const double theta = 0.5 * kPiD * (k + 0.5) / out.g_theta;
        double s = 1.0, worst = 0.0;
        for (int a = 0; a < azimuths; ++a) {
            const double phi = out.g_phi == 1 ? 2.0 * kPiD * a / azimuths : 2.0 * kPiD * (j + 0.5) / out.g_phi;
            const std::vector<double> albedo = directional_albedo(out, spherical_direction(float(theta), float(phi)), quadrature);
            for (std::size_t c = 0; c < C; ++c) {
                worst = std::max(worst, albedo[c]);
                const double diffuse = kPiD * out.rho_d[c], specular = albedo[c] - diffuse;
                if (albedo[c] > target && specular > 0.0) s = std::min(s, std::max(0.0, (target - diffuse) / specular));
            }
        }
        needed[cell] = s;
        albedo_max[cell] = worst;
    };
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    const std::size_t max_threads = limit.threads > 0 ? std::size_t(limit.threads) : hw;
    std::vector<std::size_t> todo(cells);
    for (std::size_t cell = 0; cell < cells; ++cell) todo[cell] = cell;
    double before = 0.0;
    std::size_t measured = 0, work_estimate = cells;  // for progress: the first pass, then what follows
    for (int pass = 0; pass < limit.passes && !todo.empty(); ++pass) {
        std::atomic<std::size_t> next{0};
        auto work = [&] {
            for (std::size_t i; (i = next.fetch_add(1)) < todo.size();) measure(todo[i]);
        };
        std::vector<std::thread> pool;
        for (std::size_t t = 1; t < std::min(max_threads, todo.size()); ++t) pool.emplace_back(work);
        if (limit.progress) {
            // The calling thread works too and reports between its cells.
            for (std::size_t i; (i = next.fetch_add(1)) < todo.size();) {
                measure(todo[i]);
                limit.progress(std::min(1.0, double(measured + std::min(next.load(), todo.size())) / double(work_estimate)));
            }
        } else {
            work();
        }
        for (std::thread& t : pool) t.join();
        measured += todo.size();
        if (pass == 0) before = *std::max_element(albedo_max.begin(), albedo_max.end());
        const bool last = pass + 1 == limit.passes;
        std::vector<std::size_t> again;
        for (std::size_t cell : todo) {
            if (!(needed[cell] < 1.0)) continue;
            const double f = last ? needed[cell] : std::sqrt(needed[cell]);
            total[cell] *= f;
            for (int k = 0; k < out.G.rank; ++k) out.G.basis[std::size_t(k) * cells + cell] *= float(f);
            again.push_back(cell);
        }
        todo.swap(again);
        work_estimate = measured + todo.size() * std::size_t(limit.passes - pass - 1);
    }

    // The last half cell before the horizon. Beyond G's last centre the model continues G along
    // the line through the last two rows, G(theta) = 1.5 G_L - 0.5 G_P at the horizon itself; if
    // that stays above 0 the albedo grows like 1 / cos(theta_view) there without bound (a fitted
    // paper_white reached 14 at 89.99 degrees). So where a view almost at the horizon (99.9 % of
    // the way through the band) exceeds the target, the last row is first lowered until the line
    // reaches 0 at the horizon (G_L <= G_P / 3 in every channel with a specular term); then views
    // in the band are measured and both rows scaled together (the band's G is linear in both)
    // where they still exceed the target.
    std::size_t horizon_cells = 0;
    if (out.g_theta >= 2) {
        const std::size_t last = std::size_t(out.g_theta - 1) * std::size_t(out.g_phi);
        const std::size_t prev = std::size_t(out.g_theta - 2) * std::size_t(out.g_phi);
        auto scale_cell = [&](std::size_t cell, double f) {
            total[cell] *= f;
            for (int k = 0; k < out.G.rank; ++k) out.G.basis[std::size_t(k) * cells + cell] *= float(f);
        };
        const double theta_last = 0.5 * kPiD * (out.g_theta - 0.5) / out.g_theta;
        // The smallest factor any channel needs at a view of column j (1: none exceeds).
        auto needed_at = [&](double theta, int j) {
            double r = 1.0;
            for (int a = 0; a < azimuths; ++a) {
                const double phi = out.g_phi == 1 ? 2.0 * kPiD * a / azimuths : 2.0 * kPiD * (j + 0.5) / out.g_phi;
                const std::vector<double> albedo = directional_albedo(out, spherical_direction(float(theta), float(phi)), quadrature);
                for (std::size_t c = 0; c < C; ++c) {
                    const double diffuse = kPiD * out.rho_d[c], specular = albedo[c] - diffuse;
                    if (albedo[c] > target && specular > 0.0) r = std::min(r, std::max(0.0, (target - diffuse) / specular));
                }
            }
            return r;
        };
        for (int j = 0; j < out.g_phi; ++j) {
            if (!(needed_at(theta_last + 0.999 * (0.5 * kPiD - theta_last), j) < 1.0)) continue;
            double s = 1.0;
            for (std::size_t c = 0; c < C; ++c) {
                if (!(out.rho_s[c] > 0.f)) continue;
                const double g_last = out.G.at(c, last + std::size_t(j)), g_prev = out.G.at(c, prev + std::size_t(j));
                if (1.5 * g_last - 0.5 * g_prev > 0.0) s = std::min(s, std::max(0.0, g_prev / (3.0 * g_last)));
            }
            if (s < 1.0) {
                scale_cell(last + std::size_t(j), s);
                ++horizon_cells;
            }
        }
        for (double f : {0.5, 0.9, 0.99, 0.999}) {
            const double theta = theta_last + f * (0.5 * kPiD - theta_last);
            for (int j = 0; j < out.g_phi; ++j) {
                const double r = needed_at(theta, j);
                if (r < 1.0) {
                    scale_cell(last + std::size_t(j), r);
                    scale_cell(prev + std::size_t(j), r);
                    ++horizon_cells;
                }
            }
        }
    }

    std::size_t scaled = 0;
    double smallest = 1.0, theta_lo = 90.0, theta_hi = 0.0;
    for (std::size_t cell = 0; cell < cells; ++cell) {
        if (!(total[cell] < 1.0)) continue;
        ++scaled;
        smallest = std::min(smallest, total[cell]);
        const double theta = 90.0 * (double(cell / std::size_t(out.g_phi)) + 0.5) / out.g_theta;
        theta_lo = std::min(theta_lo, theta);
        theta_hi = std::max(theta_hi, theta);
    }

    // npf convert's energy metadata describes what the file holds: measured again.
    if (has_metadata(out, "albedo_max") && (scaled > 0 || diffuse_capped > 0)) {
        const EnergyCheck e = energy_check(out, limit.threads);
        set_metadata(out, "albedo_max", detail::num(e.albedo_max));
        set_metadata(out, "albedo_max_view_theta", detail::num(e.theta_deg));
    }

    if (record) {
        std::string s = "cap " + detail::num(limit.cap) + ": largest albedo at the " + std::to_string(cells) +
                        " G cell centres " + detail::num(before, 4) + " before; ";
        if (scaled == 0) {
            s += "no cell scaled";
        } else {
            s += std::to_string(scaled) + " of " + std::to_string(cells) + " G cells scaled (views " +
                 detail::num(theta_lo, 4) + " to " + detail::num(theta_hi, 4) + " deg), smallest factor " +
                 detail::num(smallest, 4);
        }
        if (horizon_cells > 0) s += "; the last half cell before the horizon lowered (" + std::to_string(horizon_cells) + " cell steps)";
        if (diffuse_capped > 0) {
            s += "; " + std::to_string(diffuse_capped) + " channel(s) whose diffuse term alone reached the cap: rho_d = cap / pi, rho_s = 0";
        }
        record->summary = s;
    }
    return out;
}

}  // namespace npf::edit
