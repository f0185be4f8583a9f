// Rec. 709 luminance weights as ITU-R BT.709 prints them (4 digits). The sampling densities
// (environment map, NPF closure), the RGL writer's luminance field and the synthetic RGL files of
// the tests use these. Colour conversion (npf::color::linear_srgb_luminance) uses the Y row it
// derives from the primaries instead (0.2126390 0.7151687 0.0721923), so that Y agrees with
// linear_srgb_to_xyz. The two differ by ~3e-5 relative: swapping either changes written files.
#pragma once

namespace npf {

inline constexpr double kRec709Luminance[3] = {0.2126, 0.7152, 0.0722};

// Y of linear Rec. 709 RGB, in double (a float argument converts exactly).
inline double rec709_luminance(double r, double g, double b) {
    return kRec709Luminance[0] * r + kRec709Luminance[1] * g + kRec709Luminance[2] * b;
}

}  // namespace npf
