// libFuzzer target: the Neural BRDF reader (HDF5 through its C API, the checks that a network is
// read from its own file alone, the value bound) and, for networks it accepts, evaluation, pdf
// and sampling; an accepted network whose value at a fixed pair is not finite or exceeds its
// value bound is a failure (trap), as the bound promises both.
#include "fuzz_exercise.h"
#include "fuzz_input_file.h"

#include <npf/materials/nbrdf_brdf.h>
#include <npf/core/error.h>

#include <cmath>

namespace {

void check_bound(const npf::Brdf& brdf) {
    const npf::ChannelQuery q = brdf.native_query();
    const npf::Vec3 dirs[] = {{0.f, 0.f, 1.f}, {0.6f, 0.f, 0.8f}, {0.f, -0.96f, 0.28f}, {-0.8f, 0.1f, 0.59160799f},
                              {0.99f, 0.1f, 0.099498743f}, {0.f, 0.9999f, 0.01414178f}};
    float out[3];
    for (const npf::Vec3& wi : dirs)
        for (const npf::Vec3& wo : dirs) {
            brdf.eval_cos(wi, wo, q, out);
            for (float v : out)
                if (!std::isfinite(v) || double(std::fabs(v)) * wi.z > brdf.info().value_bound) __builtin_trap();
        }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string path = npf::fuzz::scratch_file(".h5");
    if (!npf::fuzz::write_scratch(path, data, size)) return 0;
    try {
        const auto brdf = npf::NbrdfBrdf::load(path);
        npf::fuzz::exercise(*brdf);
        check_bound(*brdf);
    } catch (const npf::Error&) {
        // Rejected with a message: what a reader should do with bad input.
    }
    return 0;
}
