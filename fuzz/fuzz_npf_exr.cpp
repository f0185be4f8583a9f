// libFuzzer target: the NPF factor texture reader as a tool meets it: the format sniff of
// open_material, the header walk, OpenEXR through OpenImageIO, every check of docs/format.md sec. 8,
// and for files it accepts the NpfBrdf built on them; then is_npf_texture. OpenEXR decoding costs
// about 2 ms an input (Release, no sanitizer), so this target is slow; the header walk and
// OpenEXR's header reading are fuzzed in memory at speed by npf_fuzz_exr_header.
#include "fuzz_exercise.h"
#include "fuzz_input_file.h"

#include <npf/materials/open_material.h>
#include <npf/core/error.h>
#include <npf/shading/npf_texture_file.h>

#include <OpenImageIO/imageio.h>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    OIIO::attribute("threads", 1);  // no worker threads: one input at a time, reproducibly
    OIIO::attribute("exr_threads", -1);  // nor OpenEXR's pool (a quarter faster without the handoffs)
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string path = npf::fuzz::scratch_file(".exr");
    if (!npf::fuzz::write_scratch(path, data, size)) return 0;
    try {
        npf::fuzz::exercise(*npf::open_material(path));
    } catch (const npf::Error&) {
    }
    (void)npf::is_npf_texture(path);
    OIIO::geterror();  // do not let OIIO's error text accumulate across inputs
    return 0;
}
