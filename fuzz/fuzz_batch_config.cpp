// libFuzzer target: the batch configuration parser (YAML through yaml-cpp, every key's checks)
// and, for configurations it accepts, the settings mapping and the content hash's settings text.
#include <npf/batch/config.h>
#include <npf/core/error.h>

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    // Relative globs are expanded against a folder that does not exist: cheap. An absolute one
    // with a wildcard walks the machine's own file system (a glob of /?*?*/??*/... took the
    // fuzzer past its 20 s timeout): that is what the user asked for, not a fault of the parser,
    // so such inputs are skipped.
    if (text.find_first_of("*?[") != std::string::npos) {
        if (text.find("..") != std::string::npos) return 0;  // out of that folder, after normalising
        for (std::size_t at = text.find('/'); at != std::string::npos; at = text.find('/', at + 1)) {
            const char before = at == 0 ? ' ' : text[at - 1];
            if (std::string(" \t\n\r'\"[,:-{").find(before) != std::string::npos) return 0;
        }
    }
    try {
        const npf::batch::BatchConfig c = npf::batch::parse_batch_config(text, "fuzz.yaml", "/nonexistent-npf-fuzz");
        for (const npf::batch::MaterialJob& job : c.materials) {
            (void)npf::batch::canonical_settings(job.settings);
            (void)npf::batch::resolve_render_check(job.settings);
            for (bool isotropic : {true, false}) (void)npf::batch::resolve_convert_settings(job.settings, isotropic);
        }
    } catch (const npf::Error&) {
    }
    return 0;
}
