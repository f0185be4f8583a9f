// Walker's alias method (Walker 1977, built with Vose's numerically stable two-list variant):
// draws index i with probability weight[i] / sum(weight) in O(1) from one uniform number, and
// hands back what is left of that number's randomness for the caller's next dimension.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace npf {

class AliasTable {
public:
    AliasTable() = default;
    // Weights must be finite and non-negative with a positive sum; throws npf::Error (source
    // "alias table") otherwise. Built in double, stored in float.
    explicit AliasTable(const std::vector<double>& weights);

    struct Draw {
        std::uint32_t index = 0;
        float remainder = 0.f;  // uniform in [0, 1), independent of the index
    };
    // `u` in [0, 1). Never returns an index of zero probability.
    Draw sample(float u) const;

    // Probability of index i (weight[i] / sum).
    float pmf(std::size_t i) const { return m_bins[i].pmf; }
    std::size_t size() const { return m_bins.size(); }
    bool empty() const { return m_bins.empty(); }

    struct Bin {
        float keep = 1.f;         // probability of keeping this bin once chosen
        std::uint32_t alias = 0;  // the bin taken otherwise
        float pmf = 0.f;
    };
    // The bins, for the batched closure's vector draw (sample()'s steps on four numbers).
    const std::vector<Bin>& bins() const { return m_bins; }

private:
    std::vector<Bin> m_bins;
};

}  // namespace npf
