// libFuzzer target: the MERL .binary reader (header, dimensions against the file size, values)
// and, for inputs it accepts, evaluation, pdf and sampling with both lookups.
#include "fuzz_exercise.h"
#include "fuzz_input_file.h"

#include <npf/materials/merl_brdf.h>
#include <npf/core/error.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string path = npf::fuzz::scratch_file(".binary");
    if (!npf::fuzz::write_scratch(path, data, size)) return 0;
    for (const npf::MerlLookup lookup : {npf::MerlLookup::Nearest, npf::MerlLookup::Linear}) {
        try {
            npf::MerlOptions options;
            options.lookup = lookup;
            npf::fuzz::exercise(*npf::MerlBrdf::load(path, options));
        } catch (const npf::Error&) {
        }
    }
    return 0;
}
