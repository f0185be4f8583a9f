// How the batch writes its figures in text (private to npf_batch): the progress lines and the
// Markdown summary alike.
#pragma once

#include <cstdint>
#include <string>

namespace npf::batch::detail {

// `v` with `digits` decimals ("%.*f").
std::string fixed(double v, int digits);
// "47.10", or "inf" for an infinite PSNR (renders that agree exactly).
std::string decibels(double v);
// "0.007": bytes in MB with three decimals.
std::string megabytes(std::uint64_t bytes);

}  // namespace npf::batch::detail
