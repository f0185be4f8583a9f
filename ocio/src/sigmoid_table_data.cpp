// sigmoid_table(): the table the build fitted (the generated sigmoid_table_bits.cpp).
#include "sigmoid_fit.h"

#include <cstdint>
#include <cstring>
#include <utility>

namespace npf::color::detail {

extern const std::uint32_t kSigmoidTableBits[SigmoidTable::kValues];

const SigmoidTable& sigmoid_table() {
    static const SigmoidTable table = [] {  // C++11: initialised once, other callers wait
        std::vector<float> c(SigmoidTable::kValues);
        std::memcpy(c.data(), kSigmoidTableBits, sizeof kSigmoidTableBits);
        return SigmoidTable(std::move(c));
    }();
    return table;
}

}  // namespace npf::color::detail
