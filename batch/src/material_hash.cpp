#include "material_hash.h"

#include <npf/batch/content_hash.h>
#include <npf/batch/runner.h>
#include <npf/converter/convert_settings_table.h>
#include <npf/core/version.h>
#include <npf/materials/yaml_context.h>
#include <npf/render/lighting.h>
#include <npf/shading/npf_texture_layout.h>

#include <algorithm>

namespace npf::batch {

namespace {

// The recipe's bytes and those of every file a value in it names (materials, spectra), so that
// changing a referenced file redoes the edit.
std::string edit_hash_text(const std::string& recipe) {
    std::string t = "edit " + sha256_file(recipe) + "\n";
    for (const auto& [name, path] : files_named_in_yaml(recipe)) t += "edit-file " + name + " " + sha256_file(path) + "\n";
    return t;
}

}  // namespace

namespace detail {

std::string material_hash_of(const MaterialJob& job, bool source_isotropic, const std::string& input_sha) {
    std::string t = "npf batch content hash " + std::to_string(kContentHashVersion) + "\n";
    t += std::string("npf ") + version() + ", texture format " + std::to_string(npf_exr::kFormatVersion) + "\n";
    t += "input " + input_sha + "\n";
    const ConvertSettings settings = resolve_convert_settings(job.settings, source_isotropic);
    const bool isotropic = settings.isotropy == Isotropy::Auto ? source_isotropic : settings.isotropy == Isotropy::Isotropic;
    t += convert_settings_hash_text(settings, isotropic);
    const auto e = job.settings.find("edit");
    t += (e == job.settings.end() || e->second.value.empty()) ? "edit none\n" : edit_hash_text(e->second.value);
    return sha256_hex(t);
}

std::string render_hash_of(const std::string& material_hash, const RenderCheck& check) {
    std::string text = material_hash + "\nrender size=" + std::to_string(check.size) + " spp=" + std::to_string(check.spp) +
                       " seed=" + std::to_string(check.seed) + " sampling=env floor=paired\n";
    const std::vector<std::string>& names = render::builtin_lighting_names();
    for (const std::string& l : check.lightings) {
        const bool named = std::find(names.begin(), names.end(), l) != names.end();
        text += "env " + (named ? "lighting " + l : sha256_file(l)) + "\n";
    }
    return sha256_hex(text);
}

}  // namespace detail

std::string material_hash(const MaterialJob& job, bool source_isotropic) {
    return detail::material_hash_of(job, source_isotropic, sha256_file(job.input));
}

}  // namespace npf::batch
