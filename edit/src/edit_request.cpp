#include <npf/edit/edit_request.h>

#include <npf/core/error.h>
#include <npf/edit/edit_kinds.h>
#include <npf/shading/npf_texture_file.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>

namespace npf::edit {

const std::vector<EditRunFlag>& edit_run_flags() {
    static const std::vector<EditRunFlag> flags = [] {
        std::vector<EditRunFlag> f;
        for (const EditKind& kind : edit_kinds()) {
            for (const EditFlag& e : kind.flags) f.push_back({e.name, e.takes_value, e.help});
        }
        f.insert(f.end(), {
            {"--phi-cells", true, "azimuth cells of D and G when an isotropic material becomes anisotropic (default 2 x theta)"},
            {"--svd", true, "rank (default: keep the input's SVD ranks) or ratio (the input's kept ratio)"},
            {"--albedo-tolerance", true, "warn when the directional albedo exceeds 1 + this (default 0.005)"},
            {"--no-albedo-check", false, "skip the directional-albedo check after each step"},
            {"--description", true, "the edited material's description"},
        });
        return f;
    }();
    return flags;
}

EditRequest edit_request(const std::string& recipe_path, const std::vector<std::pair<std::string, std::string>>& flags) {
    EditRecipe recipe;
    if (!recipe_path.empty()) recipe = load_edit_recipe(recipe_path);
    EditRequest request{recipe.steps, recipe.options};
    const EditKinds& kinds = edit_kinds();
    GivenFlags given;
    for (const auto& [flag, value] : flags) {
        bool known = false;
        for (const EditRunFlag& f : edit_run_flags()) known = known || f.name == flag;
        if (!known) throw Error(flag, "not an edit flag (npf edit --help lists them)");
        given[flag] = value;
    }
    check_edit_settings(kinds, given);
    for (const auto& [flag, value] : flags) {
        if (std::optional<EditStep> s = edit_step_from_flag(kinds, flag, value, given)) request.steps.push_back(std::move(*s));
    }
    EditOptions& options = request.options;
    if (given.count("--phi-cells")) {
        const double v = flag_number("--phi-cells", given.at("--phi-cells"));
        if (v != std::floor(v) || v < 0 || v > 4096) throw Error("--phi-cells", "expects a whole number in [0, 4096]");
        options.ndf.phi_cells = int(v);
    }
    if (given.count("--svd")) {
        const std::string& v = given.at("--svd");
        if (v == "rank") options.ndf.recompress = Recompress::KeepRank;
        else if (v == "ratio") options.ndf.recompress = Recompress::KeptRatio;
        else throw Error("--svd", "'" + v + "' is not rank or ratio");
    }
    if (given.count("--albedo-tolerance")) {
        options.albedo_tolerance = flag_number("--albedo-tolerance", given.at("--albedo-tolerance"));
        if (options.albedo_tolerance < 0.0) throw Error("--albedo-tolerance", "must not be negative");
    }
    if (given.count("--no-albedo-check")) options.check_albedo = false;
    if (given.count("--description")) options.description = given.at("--description");
    if (request.steps.empty() && recipe_path.empty()) {
        throw Error("edit", "no edits given (flags or --recipe; configs/edits/identity.yaml is the identity)");
    }
    return request;
}

void require_npf_texture(const std::string& path, const std::string& origin) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return;
    std::ifstream in(path, std::ios::binary);
    unsigned char head[4] = {};
    if (!in.read(reinterpret_cast<char*>(head), sizeof head) || has_exr_magic(head, sizeof head)) return;
    const Error e(path, "not an NPF factor texture; npf edit works on fitted materials (convert it first: npf convert)");
    if (origin.empty()) throw e;
    throw Error(origin, e.what());  // as apply_edits names a step's errors
}

void require_npf_textures(const std::string& input, const EditRequest& request) {
    require_npf_texture(input, "");
    for (const EditStep& s : request.steps) {
        if (s.kind == EditStep::Kind::DiffuseMaterial || s.kind == EditStep::Kind::SpecularMaterial)
            require_npf_texture(s.path, s.origin);
    }
}

}  // namespace npf::edit
