#include "figure_text.h"

#include <cmath>
#include <cstdio>

namespace npf::batch::detail {

std::string fixed(double v, int digits) {
    char b[40];
    std::snprintf(b, sizeof b, "%.*f", digits, v);
    return b;
}

std::string decibels(double v) { return std::isfinite(v) ? fixed(v, 2) : "inf"; }

std::string megabytes(std::uint64_t bytes) { return fixed(double(bytes) / 1e6, 3); }

}  // namespace npf::batch::detail
