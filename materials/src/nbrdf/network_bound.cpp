// The value bound of a Neural BRDF network (network_bound.h).
#include "network_bound.h"

#include <npf/materials/nbrdf_brdf.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace npf::nbrdf {

// An upper bound of f_r cos(theta_i) cos(theta_o) over every direction pair (brdf.h), by
// interval arithmetic through the network. A pair enters as (sin theta_h, 0, cos theta_h, d),
// d the unit difference vector, whose d.z = cos theta_d is >= 0 (wo . h >= 0); so the input
// domain is the box theta_h, theta_d in [0, pi/2], phi_d in [0, 2 pi], with
// d = (sin theta_d cos phi_d, sin theta_d sin phi_d, cos theta_d). Rotating d back gives
// cos theta_o = d.z cos theta_h - d.x sin theta_h, and wi, the mirror of wo about h,
// cos theta_i = d.z cos theta_h + d.x sin theta_h: their product is (d.z cos theta_h)^2 -
// (d.x sin theta_h)^2. Over the whole box the bound is loose (a published network's is up to
// 1e25); split into boxes, each bounded separately, it comes within a small factor of the
// network's true maximum.

namespace {

struct Interval {
    double lo, hi;
};

constexpr double kPiDouble = 3.14159265358979323846;  // npf::kPi is a float

// sin over [a, b], b - a <= 2 pi, both in [0, 3 pi].
Interval sin_over(double a, double b) {
    Interval r{std::min(std::sin(a), std::sin(b)), std::max(std::sin(a), std::sin(b))};
    for (double peak = kPiDouble / 2; peak <= b; peak += 2 * kPiDouble)
        if (peak >= a) r.hi = 1;
    for (double trough = 3 * kPiDouble / 2; trough <= b; trough += 2 * kPiDouble)
        if (trough >= a) r.lo = -1;
    return r;
}

Interval cos_over(double a, double b) { return sin_over(a + kPiDouble / 2, b + kPiDouble / 2); }

Interval times(const Interval& x, const Interval& y) {
    const double p[4] = {x.lo * y.lo, x.lo * y.hi, x.hi * y.lo, x.hi * y.hi};
    return {*std::min_element(p, p + 4), *std::max_element(p, p + 4)};
}

// The network's inputs are computed in float from directions that are unit vectors to float
// precision: each lies within this of its value for the exact angles.
constexpr double kInputSlack = 1e-5;
// Bounding stops at this many boxes, or at this much work (interval multiply-adds), or when the
// bound is within a factor of 2 of a value the network reaches; it is sound whenever it stops.
constexpr int kMaxBoundBoxes = 4096;
constexpr double kMaxBoundWork = 1 << 23;

struct AngleBox {
    double lo[3], hi[3];  // theta_h, theta_d, phi_d
};

struct BoxBound {
    // Whether a pair with both directions above the horizon may lie in the box: eval_cos
    // evaluates the network for those alone (at their exact angles, inputs rounded).
    bool reachable = false;
    double value = 0;       // bound of |f_r| cos(theta_i) cos(theta_o) over the box
    double activation = 0;  // bound of |a| over every unit, hidden and output, before ReLU
    double output = 0;      // bound of the outputs x (before exp(x) - 1)
    bool overflows() const { return reachable && (!(activation <= kMaxActivation) || !(output <= kMaxOutput)); }
};

BoxBound bound_over(const LayerView (&layers)[3], const AngleBox& box) {
    const Interval hx = sin_over(box.lo[0], box.hi[0]), hz = cos_over(box.lo[0], box.hi[0]);
    const Interval sin_d = sin_over(box.lo[1], box.hi[1]), dz = cos_over(box.lo[1], box.hi[1]);
    const Interval dx = times(sin_d, cos_over(box.lo[2], box.hi[2]));
    const Interval dy = times(sin_d, sin_over(box.lo[2], box.hi[2]));

    Interval a[NbrdfBrdf::kMaxHiddenUnits], b[NbrdfBrdf::kMaxHiddenUnits];
    double magnitude[NbrdfBrdf::kMaxHiddenUnits];
    const Interval input[NbrdfBrdf::kInputs] = {hx, {0, 0}, hz, dx, dy, dz};
    for (int i = 0; i < NbrdfBrdf::kInputs; ++i) a[i] = {input[i].lo - kInputSlack, input[i].hi + kInputSlack};
    Interval* x = a;
    Interval* y = b;
    BoxBound r;
    for (int k = 0; k < kLayerCount; ++k) {
        const LayerView& l = layers[k];
        for (int j = 0; j < l.units; ++j) {
            y[j] = {double(l.bias[j]), double(l.bias[j])};
            magnitude[j] = std::fabs(double(l.bias[j]));
        }
        for (int i = 0; i < l.inputs; ++i) {
            const Interval xi = x[i];
            const double size = std::max(std::fabs(xi.lo), std::fabs(xi.hi));
            const float* row = l.kernel + static_cast<std::size_t>(i) * l.stride;
            for (int j = 0; j < l.units; ++j) {
                const double w = row[j];
                y[j].lo += w * (w >= 0 ? xi.lo : xi.hi);
                y[j].hi += w * (w >= 0 ? xi.hi : xi.lo);
                magnitude[j] += std::fabs(w) * size;
            }
        }
        const bool last = k + 1 == kLayerCount;
        for (int j = 0; j < l.units; ++j) {
            // The float forward pass rounds each product and partial sum: its result is within
            // (n + 1) 2^-24 of the sum of |terms| of the exact one (n terms and the bias).
            const double rounding = (l.inputs + 2) * std::ldexp(1.0, -23) * magnitude[j];
            y[j].lo -= rounding;
            y[j].hi += rounding;
            const double largest = std::max({magnitude[j] + rounding, std::fabs(y[j].lo), std::fabs(y[j].hi)});
            // NaN (inf - inf on absurd weights) is no bound: infinite.
            r.activation = largest <= std::numeric_limits<double>::max() ? std::max(r.activation, largest)
                                                                          : std::numeric_limits<double>::infinity();
            if (!last) y[j] = {std::max(y[j].lo, 0.0), std::max(y[j].hi, 0.0)};
        }
        std::swap(x, y);
    }

    // cos(theta_i) cos(theta_o) = A^2 - B^2 with A = d.z cos theta_h >= 0 and B = d.x sin theta_h,
    // from the exact angles (the box holds them; only the inputs carry rounding).
    const Interval big_a = times(dz, hz), big_b = times(dx, hx);
    const double b_squared_lo = big_b.lo <= 0 && big_b.hi >= 0 ? 0.0 : std::min(big_b.lo * big_b.lo, big_b.hi * big_b.hi);
    const double cosines = std::min(1.0, std::max(big_a.lo * big_a.lo, big_a.hi * big_a.hi) - b_squared_lo);
    // A box with no pair above the horizon on both sides (cosines <= 0) gives nothing.
    r.reachable = cosines > 0;
    if (!r.reachable) return {};
    r.output = -std::numeric_limits<double>::infinity();
    for (int c = 0; c < NbrdfBrdf::kOutputs; ++c) {
        r.output = std::max(r.output, x[c].hi);
        // exp(x) - 1 >= -1; float's expm1 and the final products round: a margin of 2^-20.
        const double f = std::max(std::expm1(x[c].hi), -std::expm1(x[c].lo));
        r.value = std::max(r.value, f * cosines * (1 + std::ldexp(1.0, -20)));
    }
    if (!(r.value >= 0)) r.value = std::numeric_limits<double>::infinity();
    if (std::isnan(r.output)) r.output = std::numeric_limits<double>::infinity();
    return r;
}

// f_r cos(theta_i) cos(theta_o) at the centre of a box, in double: a value the network reaches
// (up to its float rounding), so the largest seen is a lower bound of the true maximum.
double value_at_centre(const LayerView (&layers)[3], const AngleBox& box) {
    const double theta_h = 0.5 * (box.lo[0] + box.hi[0]), theta_d = 0.5 * (box.lo[1] + box.hi[1]),
                 phi_d = 0.5 * (box.lo[2] + box.hi[2]);
    double x[NbrdfBrdf::kMaxHiddenUnits], y[NbrdfBrdf::kMaxHiddenUnits];
    const double dx = std::sin(theta_d) * std::cos(phi_d), dz = std::cos(theta_d);
    const double dy = std::sin(theta_d) * std::sin(phi_d);
    const double input[NbrdfBrdf::kInputs] = {std::sin(theta_h), 0, std::cos(theta_h), dx, dy, dz};
    std::copy(input, input + NbrdfBrdf::kInputs, x);
    for (int k = 0; k < kLayerCount; ++k) {
        const LayerView& l = layers[k];
        for (int j = 0; j < l.units; ++j) y[j] = l.bias[j];
        for (int i = 0; i < l.inputs; ++i)
            for (int j = 0; j < l.units; ++j) y[j] += x[i] * double(l.kernel[static_cast<std::size_t>(i) * l.stride + j]);
        for (int j = 0; j < l.units; ++j) x[j] = k + 1 < kLayerCount ? std::max(y[j], 0.0) : y[j];
    }
    const double a = dz * std::cos(theta_h), b = dx * std::sin(theta_h);
    const double cosines = std::max(0.0, a * a - b * b);
    double best = 0;
    for (int c = 0; c < NbrdfBrdf::kOutputs; ++c) best = std::max(best, std::expm1(x[c]) * cosines);
    return std::isfinite(best) ? best : 0.0;
}

}  // namespace

// Branch and bound: the box with the largest bound (or one whose float evaluation could
// overflow) is split in two along its widest angle, until the stopping rule above.
NetworkBound bound_network(const LayerView (&layers)[kLayerCount]) {
    struct Leaf {
        AngleBox box;
        BoxBound bound;
        double priority() const { return bound.overflows() ? std::numeric_limits<double>::infinity() : bound.value; }
    };
    const auto lower_priority = [](const Leaf& p, const Leaf& q) { return p.priority() < q.priority(); };
    double work_per_box = 0;
    for (const LayerView& l : layers) work_per_box += double(l.inputs) * l.units;
    const int budget = std::max(1, std::min(kMaxBoundBoxes, int(kMaxBoundWork / work_per_box)));

    std::vector<Leaf> leaves;
    leaves.reserve(static_cast<std::size_t>(budget) + 1);
    const AngleBox whole{{0, 0, 0}, {kPiDouble / 2, kPiDouble / 2, 2 * kPiDouble}};
    leaves.push_back({whole, bound_over(layers, whole)});
    double reached = value_at_centre(layers, whole);
    int boxes = 1;
    while (boxes + 2 <= budget) {
        const Leaf& top = leaves.front();
        if (!top.bound.overflows() && top.bound.value <= 2 * reached) break;
        std::pop_heap(leaves.begin(), leaves.end(), lower_priority);
        const AngleBox box = leaves.back().box;
        leaves.pop_back();
        int axis = 0;
        double widest = -1;
        for (int k = 0; k < 3; ++k) {
            // phi_d moves d by sin theta_d per radian, at most: half the weight of the thetas'.
            const double width = (box.hi[k] - box.lo[k]) * (k == 2 ? 0.5 : 1.0);
            if (width > widest) widest = width, axis = k;
        }
        const double middle = 0.5 * (box.lo[axis] + box.hi[axis]);
        AngleBox halves[2] = {box, box};
        halves[0].hi[axis] = middle;
        halves[1].lo[axis] = middle;
        for (const AngleBox& half : halves) {
            leaves.push_back({half, bound_over(layers, half)});
            std::push_heap(leaves.begin(), leaves.end(), lower_priority);
            reached = std::max(reached, value_at_centre(layers, half));
        }
        boxes += 2;
    }
    NetworkBound r;
    r.boxes = boxes;
    r.output = -std::numeric_limits<double>::infinity();
    for (const Leaf& leaf : leaves) {
        if (!leaf.bound.reachable) continue;
        r.value = std::max(r.value, leaf.bound.value);
        r.activation = std::max(r.activation, leaf.bound.activation);
        r.output = std::max(r.output, leaf.bound.output);
    }
    return r;
}

}  // namespace npf::nbrdf
