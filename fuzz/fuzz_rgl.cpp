// libFuzzer target: the RGL .bsdf reader (tensor_file container, field checks, tables) and, for
// inputs it accepts, evaluation, pdf and sampling.
#include "fuzz_exercise.h"

#include <npf/materials/rgl_brdf.h>
#include <npf/materials/tensor_file.h>
#include <npf/core/error.h>

#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const npf::TensorFile file = npf::TensorFile::parse(std::vector<std::uint8_t>(data, data + size), "fuzz.bsdf");
        npf::fuzz::exercise(*npf::RglBrdf::from_tensor_file(file));
    } catch (const npf::Error&) {
        // Rejected with a message: what a reader should do with bad input.
    }
    return 0;
}
