#include "sample_set.h"

#include <npf/core/error.h>
#include <npf/core/parallel.h>
#include <npf/core/vec.h>
#include <npf/shading/npf_equation.h>

#include <algorithm>
#include <cmath>

namespace npf::fit_detail {

namespace {

int g_theta_cell(double z, int n) { return equation::g_owner_row(std::acos(std::clamp(z, -1.0, 1.0)), n); }

// The theta neighbour of a direction's owner G cell and its interpolation weight: linear between
// the two rows, and beyond the last centre the line through the last two rows (G's horizon rule,
// npf_equation.h).
void g_theta_neighbour(double z, int n, int owner_row, int& neighbour_row, float& weight) {
    const double x = equation::theta_cells(std::acos(std::clamp(z, -1.0, 1.0)), n) - 0.5;  // centres at integers
    const double d = x - owner_row;
    if (d >= 0.0) {
        neighbour_row = owner_row + 1 < n ? owner_row + 1 : owner_row - 1;
        weight = float(owner_row + 1 < n ? d : -d);
    } else {
        neighbour_row = owner_row > 0 ? owner_row - 1 : owner_row;
        weight = float(owner_row > 0 ? -d : 0.0);
    }
}

int g_phi_cell(double x, double y, int n) {
    if (n == 1) return 0;
    double phi = std::atan2(y, x);
    if (phi < 0.0) phi += kTwoPiD;
    return std::min(int(phi * equation::kInvTwoPi * n), n - 1);
}

// A fixed pseudo-random rotation in [0, 1) per ring: stratified phi_d samples whose positions
// differ from ring to ring, so that subsampling does not alias with the material's structure.
double ring_offset(int ih, int jh, int id) {
    std::uint64_t x = std::uint64_t(ih) * 0x9E3779B97F4A7C15ull ^ std::uint64_t(jh) * 0xC2B2AE3D27D4EB4Full ^
                      std::uint64_t(id) * 0x165667B19E3779F9ull;
    x ^= x >> 31;
    x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 29;
    return double(x >> 11) * 0x1.0p-53;
}

// w_V of a sample, the measure of the cell it stands for.
double volume_weight(const AwlsOptions& o, int ih, int id, int phi_d_samples) {
    const RusinkiewiczGrid& g = o.grid;
    const double cell = g.volume_weight(ih, id) * double(g.phi_d) / double(phi_d_samples);
    if (o.volume_weight == VolumeWeight::Paper) return cell;
    // Three-angle form: our reading of Bagher et al.'s weight applied to the sqrt-mapped grid,
    // i.e. without the Jacobian d(theta_h) = pi u du of the square-root map (docs/fitting.md).
    const double u = (ih + 0.5) / g.theta_h;
    return cell / (kPiD * u) * kHalfPiD;
}

struct Part {
    std::vector<std::uint32_t> cell_rings;  // rings per D cell
    std::vector<std::uint32_t> ring_sizes;
    std::vector<std::uint16_t> ring_f;
    std::vector<std::uint32_t> gi, go, gi2, go2;
    std::vector<float> ti, to, inv_cc, geometry, directions;
};

}  // namespace

SampleSet make_sample_set(const AwlsOptions& o, int threads) {
    const RusinkiewiczGrid& grid = o.grid;
    const int phi_d_samples = o.phi_d_samples > 0 ? o.phi_d_samples : grid.phi_d;
    const bool centred = phi_d_samples == grid.phi_d;
    // One part per thread, each a run of theta_h rows, joined in row order below.
    std::vector<Part> parts(std::size_t(std::max(1, threads)));
    npf::parallel_slices(std::size_t(grid.theta_h), parts.size(), [&](std::size_t t, std::size_t b, std::size_t e) {
        Part& p = parts[t];
        for (int ih = int(b); ih < int(e); ++ih) {
            for (int jh = 0; jh < grid.phi_h; ++jh) {
                std::uint32_t rings = 0;
                for (int id = 0; id < grid.theta_d; ++id) {
                    const double wv = volume_weight(o, ih, id, phi_d_samples);
                    const double offset = centred ? 0.5 : ring_offset(ih, jh, id);
                    std::uint32_t count = 0;
                    for (int k = 0; k < phi_d_samples; ++k) {
                        const HalfDiff a{grid.theta_h_at(ih), grid.phi_h_at(jh), grid.theta_d_at(id),
                                         kTwoPiD * (k + offset) / phi_d_samples};
                        Vec3d wi, wo;
                        directions_from_half_diff(a, wi, wo);
                        if (!(wi.z > 1e-6) || !(wo.z > 1e-6)) continue;
                        auto add_direction = [&](const Vec3d& w, std::vector<std::uint32_t>& owner, std::vector<std::uint32_t>& neighbour,
                                                 std::vector<float>& weights) {
                            const int row = g_theta_cell(w.z, o.g_theta), col = g_phi_cell(w.x, w.y, o.g_phi);
                            int row2 = row;
                            float weight = 0.f;
                            g_theta_neighbour(w.z, o.g_theta, row, row2, weight);
                            owner.push_back(std::uint32_t(row * o.g_phi + col));
                            neighbour.push_back(std::uint32_t(row2 * o.g_phi + col));
                            weights.push_back(weight);
                        };
                        add_direction(wi, p.gi, p.gi2, p.ti);
                        add_direction(wo, p.go, p.go2, p.to);
                        p.inv_cc.push_back(float(1.0 / (wi.z * wo.z)));
                        p.geometry.push_back(float(wv * std::pow(wi.z, o.importance_power_view) * std::pow(wo.z, o.importance_power_light)));
                        for (double v : {wi.x, wi.y, wi.z, wo.x, wo.y, wo.z}) p.directions.push_back(float(v));
                        ++count;
                    }
                    if (count == 0) continue;
                    p.ring_sizes.push_back(count);
                    p.ring_f.push_back(std::uint16_t(id));
                    ++rings;
                }
                p.cell_rings.push_back(rings);
            }
        }
    }, int(parts.size()));

    SampleSet s;
    s.d_cells = std::size_t(grid.theta_h) * std::size_t(grid.phi_h);
    s.f_cells = std::size_t(grid.theta_d);
    s.g_cells = std::size_t(o.g_theta) * std::size_t(o.g_phi);
    std::size_t total = 0, rings = 0;
    for (const Part& p : parts) total += p.gi.size(), rings += p.ring_f.size();
    if (total == 0) throw Error("fit", "the grid has no sample with both directions above the horizon");
    if (total >= (std::size_t(1) << 32)) throw Error("fit", "too many samples for one fit (reduce the grid or phi_d samples)");
    for (auto* v : {&s.gi, &s.go, &s.gi2, &s.go2}) v->reserve(total);
    for (auto* v : {&s.ti, &s.to, &s.inv_cc}) v->reserve(total);
    s.go.reserve(total);
    s.geometry.reserve(total);
    s.directions.reserve(6 * total);
    s.ring_f.reserve(rings);
    s.ring_begin.reserve(rings + 1);
    s.cell_ring_begin.reserve(s.d_cells + 1);
    s.ring_begin.push_back(0);
    s.cell_ring_begin.push_back(0);
    for (Part& p : parts) {
        for (std::uint32_t n : p.ring_sizes) s.ring_begin.push_back(s.ring_begin.back() + n);
        for (std::uint32_t n : p.cell_rings) s.cell_ring_begin.push_back(s.cell_ring_begin.back() + n);
        s.ring_f.insert(s.ring_f.end(), p.ring_f.begin(), p.ring_f.end());
        s.gi.insert(s.gi.end(), p.gi.begin(), p.gi.end());
        s.gi2.insert(s.gi2.end(), p.gi2.begin(), p.gi2.end());
        s.go2.insert(s.go2.end(), p.go2.begin(), p.go2.end());
        s.ti.insert(s.ti.end(), p.ti.begin(), p.ti.end());
        s.to.insert(s.to.end(), p.to.begin(), p.to.end());
        s.inv_cc.insert(s.inv_cc.end(), p.inv_cc.begin(), p.inv_cc.end());
        s.go.insert(s.go.end(), p.go.begin(), p.go.end());
        s.geometry.insert(s.geometry.end(), p.geometry.begin(), p.geometry.end());
        s.directions.insert(s.directions.end(), p.directions.begin(), p.directions.end());
        p = Part{};  // give the memory back as we go
    }
    return s;
}

std::vector<std::size_t> balanced_cell_split(const SampleSet& s, int parts) {
    std::vector<std::size_t> split{0};
    const double total = double(s.size());
    std::size_t cell = 0;
    for (int t = 1; t < parts; ++t) {
        const double target = total * t / parts;
        while (cell < s.d_cells && double(s.ring_begin[s.cell_ring_begin[cell + 1]]) < target) ++cell;
        split.push_back(std::min(cell + 1, s.d_cells));
    }
    split.push_back(s.d_cells);
    for (std::size_t t = 1; t < split.size(); ++t) split[t] = std::max(split[t], split[t - 1]);
    return split;
}

}  // namespace npf::fit_detail
