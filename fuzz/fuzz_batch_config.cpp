// libFuzzer target: the batch configuration parser (YAML through yaml-cpp, every key's checks)
// and, for configurations it accepts, the settings mapping and the content hash's settings text.
#include <npf/batch/config.h>
#include <npf/core/error.h>

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    // Globs are expanded against this folder; keep them from walking the whole file system.
    if (text.find("/*") != std::string::npos || text.find("**") != std::string::npos) return 0;
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
