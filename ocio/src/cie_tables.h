// Private to npf_color: the CIE tables behind cie_1931() and illuminant_d65().
#pragma once

namespace npf::color::detail {

// CIE 1931 2-degree colour matching functions, 1 nm apart over 360..830 nm.
inline constexpr int kCmfFirstNm = 360;
inline constexpr int kCmfLastNm = 830;
inline constexpr int kCmfCount = kCmfLastNm - kCmfFirstNm + 1;  // 471
extern const double kCie1931X[kCmfCount];
extern const double kCie1931Y[kCmfCount];
extern const double kCie1931Z[kCmfCount];

// CIE standard illuminant D65 (relative, 100 at 560 nm), 5 nm apart over 300..830 nm.
inline constexpr int kD65FirstNm = 300;
inline constexpr int kD65LastNm = 830;
inline constexpr int kD65StepNm = 5;
inline constexpr int kD65Count = (kD65LastNm - kD65FirstNm) / kD65StepNm + 1;  // 107
extern const double kD65[kD65Count];

}  // namespace npf::color::detail
