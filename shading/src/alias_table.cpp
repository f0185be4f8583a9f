#include <npf/shading/alias_table.h>

#include <npf/core/error.h>

#include <algorithm>
#include <cmath>

namespace npf {

AliasTable::AliasTable(const std::vector<double>& weights) {
    const std::size_t n = weights.size();
    if (n == 0) throw Error("alias table", "no weights");
    if (n > std::size_t(1) << 31) throw Error("alias table", "too many weights");
    double sum = 0.0;
    for (double w : weights) {
        if (!std::isfinite(w) || w < 0.0) throw Error("alias table", "weights must be finite and non-negative");
        sum += w;
    }
    if (!(sum > 0.0) || !std::isfinite(sum)) throw Error("alias table", "the weights sum to zero");

    m_bins.resize(n);
    // Scaled so that the average bin holds exactly 1.
    std::vector<double> scaled(n);
    std::vector<std::uint32_t> small, large;
    for (std::size_t i = 0; i < n; ++i) {
        m_bins[i].pmf = float(weights[i] / sum);
        scaled[i] = weights[i] / sum * double(n);
        (scaled[i] < 1.0 ? small : large).push_back(std::uint32_t(i));
    }
    while (!small.empty() && !large.empty()) {
        const std::uint32_t s = small.back(), l = large.back();
        small.pop_back();
        m_bins[s].keep = float(scaled[s]);
        m_bins[s].alias = l;
        // The large bin gives away what fills the small one (Vose: subtract in this order).
        scaled[l] = (scaled[l] + scaled[s]) - 1.0;
        if (scaled[l] < 1.0) {
            large.pop_back();
            small.push_back(l);
        }
    }
    // What remains is 1 up to rounding: such bins keep themselves.
    for (std::uint32_t i : large) m_bins[i] = Bin{1.f, i, m_bins[i].pmf};
    for (std::uint32_t i : small) m_bins[i] = Bin{1.f, i, m_bins[i].pmf};
    // A bin of zero weight must never be kept (keep = 0 exactly, alias elsewhere); one of
    // positive weight whose float keep rounded to 1 is harmless.
    const std::uint32_t heaviest = std::uint32_t(std::max_element(weights.begin(), weights.end()) - weights.begin());
    for (std::size_t i = 0; i < n; ++i) {
        if (weights[i] == 0.0) {
            m_bins[i].keep = 0.f;
            if (m_bins[i].alias == i) m_bins[i].alias = heaviest;
        }
    }
}

AliasTable::Draw AliasTable::sample(float u) const {
    const float scaled = u * float(m_bins.size());
    const std::size_t i = std::min(std::size_t(scaled), m_bins.size() - 1);
    // The fractional part decides between the bin and its alias, then is stretched back to
    // [0, 1) for the caller.
    const float f = std::min(scaled - float(i), 0x1.fffffep-1f);
    const Bin& b = m_bins[i];
    Draw d;
    if (f < b.keep) {
        d.index = std::uint32_t(i);
        d.remainder = std::min(f / b.keep, 0x1.fffffep-1f);
    } else {
        d.index = b.alias;
        d.remainder = std::min((f - b.keep) / (1.f - b.keep), 0x1.fffffep-1f);
    }
    return d;
}

}  // namespace npf
