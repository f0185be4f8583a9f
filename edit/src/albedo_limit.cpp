#include <npf/edit/albedo_limit.h>

#include "tables.h"

#include <npf/shading/npf_albedo.h>
#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/core/parallel.h>
#include <npf/shading/npf_texture_layout.h>
#include <npf/shading/npf_equation.h>

#include <algorithm>
#include <cmath>
#include <functional>
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

// The model being capped, the albedo measurements on it, and the G scaling applied so far.
class Capper {
public:
    Capper(NpfModel& capped, const AlbedoLimit& settings)
        : m(capped), limit(settings), target(settings.cap * (1.0 - settings.margin)),
          cells(std::size_t(capped.g_theta) * std::size_t(capped.g_phi)), total(cells, 1.0) {
        quadrature.u_cells = settings.u_cells;
        quadrature.phi_cells = settings.phi_cells;
        if (!m.isotropic() && settings.u_cells == 0) quadrature.u_cells = 64;
        if (!m.isotropic() && settings.phi_cells == 0) quadrature.phi_cells = 64;
        azimuths = m.g_phi == 1 && m.d_phi > 1 ? kAzimuthsPerIsotropicRow : 1;
    }

    // The factor that brings the albedo at a view of G column j to the target in every channel
    // (1: none exceeds it), and the largest albedo there.
    struct Need {
        double factor = 1.0, largest = 0.0;
    };
    Need need_at(double theta, int j) const {
        Need n;
        for (int a = 0; a < azimuths; ++a) {
            const double phi = m.g_phi == 1 ? 2.0 * kPiD * a / azimuths : 2.0 * kPiD * (j + 0.5) / m.g_phi;
            const std::vector<double> albedo = npf_directional_albedo(m, spherical_direction(float(theta), float(phi)), quadrature);
            for (std::size_t c = 0; c < albedo.size(); ++c) {
                n.largest = std::max(n.largest, albedo[c]);
                const double diffuse = kPiD * m.rho_d[c], specular = albedo[c] - diffuse;
                if (albedo[c] > target && specular > 0.0) n.factor = std::min(n.factor, std::max(0.0, (target - diffuse) / specular));
            }
        }
        return n;
    }

    void scale_cell(std::size_t cell, double f) {
        total[cell] *= f;
        for (int k = 0; k < m.G.rank; ++k) m.G.basis[std::size_t(k) * cells + cell] *= float(f);
    }

    // Passes over the G cell centres, each lowering G where the albedo exceeds the target.
    // Lowering G also lowers other views' albedo (G weighs the light side too), so when many
    // cells exceed, one exact step per cell would overshoot (a uniformly too bright material
    // would end near cap^2): the passes before the last take the square root of the needed
    // factor, the last the whole factor. A cell below the target never needs a later pass (its
    // albedo only falls), so only cells lowered in the previous pass are measured again. The
    // last pass's exact step leaves every centre at or below the target (see the header).
    // Returns the largest albedo of the first pass.
    double cap_cell_centres() {
        std::vector<Need> need(cells);
        std::vector<std::size_t> todo(cells);
        for (std::size_t cell = 0; cell < cells; ++cell) todo[cell] = cell;
        double before = 0.0;
        std::size_t measured = 0, work = cells;  // for progress: the first pass, then an estimate
        for (int pass = 0; pass < limit.passes && !todo.empty(); ++pass) {
            auto measure = [&](std::size_t i) {
                const std::size_t cell = todo[i];
                const int k = int(cell / std::size_t(m.g_phi)), j = int(cell % std::size_t(m.g_phi));
                need[cell] = need_at(equation::theta_centre(k, m.g_theta), j);
            };
            std::function<void(double)> progress;
            if (limit.progress) {
                progress = [&](double f) {
                    limit.progress(std::min(1.0, (double(measured) + f * double(todo.size())) / double(work)));
                };
            }
            parallel_for(todo.size(), measure, limit.threads, progress);
            measured += todo.size();
            if (pass == 0) {
                for (const Need& n : need) before = std::max(before, n.largest);
            }
            const bool last = pass + 1 == limit.passes;
            std::vector<std::size_t> again;
            for (std::size_t cell : todo) {
                if (!(need[cell].factor < 1.0)) continue;
                scale_cell(cell, last ? need[cell].factor : std::sqrt(need[cell].factor));
                again.push_back(cell);
            }
            todo.swap(again);
            work = measured + todo.size() * std::size_t(limit.passes - pass - 1);
        }
        return before;
    }

    // The last half cell before the horizon. Beyond G's last centre the model continues G along
    // the line through the last two rows (G's horizon rule, npf_equation.h); if that
    // stays above 0 the albedo grows like 1 / cos(theta_view) there without bound (a fitted
    // paper_white reached 18 at 89.99 degrees). So where a view almost at the horizon (99.9 % of
    // the way through the band) exceeds the target, the last row is first lowered until the line
    // reaches 0 at the horizon (G_L <= G_P / 3 in every channel with a specular term); then views
    // in the band are measured and both rows scaled together (the band's G is linear in both)
    // where they still exceed the target. Returns the number of cell steps taken.
    std::size_t cap_horizon_band() {
        if (m.g_theta < 2) return 0;
        std::size_t steps = 0;
        const std::size_t last = std::size_t(m.g_theta - 1) * std::size_t(m.g_phi);
        const std::size_t prev = std::size_t(m.g_theta - 2) * std::size_t(m.g_phi);
        const double theta_last = equation::theta_centre(m.g_theta - 1, m.g_theta);
        auto band = [&](double fraction) { return theta_last + fraction * (0.5 * kPiD - theta_last); };
        for (int j = 0; j < m.g_phi; ++j) {
            if (!(need_at(band(0.999), j).factor < 1.0)) continue;
            double s = 1.0;
            for (std::size_t c = 0; c < m.channel_count(); ++c) {
                if (!(m.rho_s[c] > 0.f) || !(m.g_at_horizon(c, j) > 0.0)) continue;
                const double g_last = m.G.at(c, last + std::size_t(j)), g_prev = m.G.at(c, prev + std::size_t(j));
                s = std::min(s, equation::g_closing_scale(g_last, g_prev));
            }
            if (s < 1.0) {
                scale_cell(last + std::size_t(j), s);
                ++steps;
            }
        }
        for (double fraction : {0.5, 0.9, 0.99, 0.999}) {
            for (int j = 0; j < m.g_phi; ++j) {
                const double r = need_at(band(fraction), j).factor;
                if (r < 1.0) {
                    scale_cell(last + std::size_t(j), r);
                    scale_cell(prev + std::size_t(j), r);
                    ++steps;
                }
            }
        }
        return steps;
    }

    NpfModel& m;
    const AlbedoLimit& limit;
    const double target;
    const std::size_t cells;
    std::vector<double> total;  // the factor applied to each G cell so far
    NpfAlbedoQuadrature quadrature;
    int azimuths = 1;
};

// How far above the cap the check's albedo may read (see limit_albedo).
constexpr double kCapTolerance = 0.01;

}  // namespace

NpfModel limit_albedo(const NpfModel& model, const AlbedoLimit& limit, EditRecord* record) {
    if (!(limit.cap > 0.0 && limit.cap <= 1.0)) {
        throw Error("limit_albedo", "the cap must be in (0, 1], got " + number_text(limit.cap));
    }
    if (!(limit.margin >= 0.0 && limit.margin < 0.1)) {
        throw Error("limit_albedo", "the margin must be in [0, 0.1), got " + number_text(limit.margin));
    }
    if (limit.passes < 1 || limit.passes > 16) {
        throw Error("limit_albedo", "passes must be in 1..16, got " + std::to_string(limit.passes));
    }
    NpfModel out = model;

    // Channels whose diffuse term alone reaches the cap leave no room for a specular term.
    int diffuse_capped = 0;
    for (std::size_t c = 0; c < out.channel_count(); ++c) {
        if (kPiD * out.rho_d[c] >= limit.cap) {
            out.rho_d[c] = float(limit.cap * (1.0 - limit.margin) / kPiD);
            out.rho_s[c] = 0.f;
            ++diffuse_capped;
        }
    }

    Capper capper(out, limit);
    const double before = capper.cap_cell_centres();
    const std::size_t horizon_steps = capper.cap_horizon_band();

    std::size_t scaled = 0;
    double smallest = 1.0, theta_lo = 90.0, theta_hi = 0.0;
    for (std::size_t cell = 0; cell < capper.cells; ++cell) {
        if (!(capper.total[cell] < 1.0)) continue;
        ++scaled;
        smallest = std::min(smallest, capper.total[cell]);
        const double theta = 90.0 * (double(cell / std::size_t(out.g_phi)) + 0.5) / out.g_theta;
        theta_lo = std::min(theta_lo, theta);
        theta_hi = std::max(theta_hi, theta);
    }

    // The cap is checked, not assumed: the albedo measured as npf convert and npf albedo measure it
    // (its own quadrature, views to the horizon) must be within it, or the edit fails rather than
    // write a file that says it was capped. The tolerance covers the two quadratures' difference
    // at grazing views of sharp lobes (docs/editing.md).
    const EnergyCheck e = energy_check(out, limit.threads);
    if (!(e.albedo_max <= limit.cap * (1.0 + kCapTolerance))) {
        throw Error("limit_albedo", "the cap " + number_text(limit.cap) + " is not met: the capped material's albedo still reaches " +
                                        number_text(e.albedo_max, 4) + " (view " + number_text(e.theta_deg, 4) + " deg)");
    }
    // npf convert's energy metadata describes what the file holds: measured again.
    if (has_metadata(out, npf_exr::kMetaAlbedoMax) && (scaled > 0 || diffuse_capped > 0)) {
        set_metadata(out, npf_exr::kMetaAlbedoMax, number_text(e.albedo_max));
        set_metadata(out, npf_exr::kMetaAlbedoMaxViewTheta, number_text(e.theta_deg));
    }

    if (record) {
        std::string s = "cap " + number_text(limit.cap) + ": largest albedo at the " + std::to_string(capper.cells) +
                        " G cell centres " + number_text(before, 4) + " before; ";
        if (scaled == 0) {
            s += "no cell scaled";
        } else {
            s += std::to_string(scaled) + " of " + std::to_string(capper.cells) + " G cells scaled (views " +
                 number_text(theta_lo, 4) + " to " + number_text(theta_hi, 4) + " deg), smallest factor " +
                 number_text(smallest, 4);
        }
        if (horizon_steps > 0) {
            s += "; the last half cell before the horizon lowered (" + std::to_string(horizon_steps) + " cell steps)";
        }
        if (diffuse_capped > 0) {
            s += "; " + std::to_string(diffuse_capped) +
                 " channel(s) whose diffuse term alone reached the cap: rho_d = cap / pi, rho_s = 0";
        }
        record->summary = s;
    }
    return out;
}

}  // namespace npf::edit
