// npf edit: edits on a fitted NPF material (paper sec. 4.3; docs/editing.md): NDF transforms,
// diffuse and specular colour swaps, thin-film Fresnel. Steps come from a YAML recipe and from
// flags (recipe first, then the flags in command-line order), both through the edit kinds
// (npf/edit/edit_kinds.h), which also give the edit flags and their help.
#include "command_line.h"
#include "commands.h"
#include "progress.h"

#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/edit/edit_kinds.h>
#include <npf/edit/recipe.h>
#include <npf/shading/npf_texture_file.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace npf::cli {

namespace {

// The edit flags come from the edit kinds (edit_kinds.h), between the command's own.
const std::vector<FlagSpec>& edit_flags() {
    static const std::vector<FlagSpec> flags = [] {
        std::vector<FlagSpec> f = {
            {"-o", true, "output factor texture (.exr); required unless --dry-run"},
            {"--recipe", true, "YAML recipe: a list of steps applied in order (configs/edits/)"},
        };
        for (const edit::EditKind& kind : edit::edit_kinds()) {
            for (const edit::EditFlag& e : kind.flags) f.push_back({e.name, e.takes_value, e.help});
        }
        f.insert(f.end(), {
            {"--phi-cells", true, "azimuth cells of D and G when an isotropic material becomes anisotropic (default 2 x theta)"},
            {"--svd", true, "rank (default: keep the input's SVD ranks) or ratio (the input's kept ratio)"},
            {"--albedo-tolerance", true, "warn when the directional albedo exceeds 1 + this (default 0.005)"},
            {"--no-albedo-check", false, "skip the directional-albedo check after each step"},
            {"--description", true, "the edited material's description"},
            {"--dry-run", false, "apply and report, write nothing"},
            {"--help", false, "show this help"},
        });
        return f;
    }();
    return flags;
}

// Edits work on fitted materials only: any other material (a measurement, a recipe), which
// `npf convert` takes, is refused by name before any work. A file that is missing, not regular,
// too short or an OpenEXR file is left to the NPF reader, whose messages say more.
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

}  // namespace

int run_edit(const std::vector<std::string>& args) {
    CommandLine cl("edit", args, edit_flags());
    const bool dry = cl.has("--dry-run");
    if (cl.has("--help")) {
        std::printf("usage: npf edit IN.exr -o OUT.exr [--recipe FILE.yaml] [edit flags]\n\n"
                    "Edits a fitted NPF material (paper sec. 4.3): NDF linear transforms and their friendly forms,\n"
                    "diffuse colour, specular colour, thin-film Fresnel. The recipe's steps run first, then the edit\n"
                    "flags in the order given; each step's record goes into the file's metadata (edit_001, ...), which\n"
                    "npf info shows. After each step the directional albedo is checked (a warning above 1).\n"
                    "Conventions, maths and limits: docs/editing.md; example recipes: configs/edits/. Examples:\n"
                    "  npf edit copper.exr -o copper_wide.exr --stretch-tangent 2 --rotate 30\n"
                    "  npf edit felt.exr -o felt_red.exr --diffuse-srgb 0.8,0.1,0.1\n"
                    "  npf edit steel.exr -o steel_film.exr --thin-film 615,1.3 --film-base fitted\n"
                    "  npf edit paper.exr -o paper_capped.exr --limit-albedo 1\n\n%s",
                    usage_lines(edit_flags()).c_str());
        return 0;
    }
    cl.expect_positional(1, 1, "one IN.exr");
    if (!dry) cl.require("-o");
    const std::string input = cl.positional()[0], output = cl.value("-o");

    // Everything that can fail on the command line fails before any work.
    edit::EditRecipe recipe;
    if (cl.has("--recipe")) recipe = edit::load_edit_recipe(cl.value("--recipe"));
    edit::EditOptions options = recipe.options;
    const edit::EditKinds& kinds = edit::edit_kinds();
    edit::GivenFlags given;
    for (const auto& [flag, value] : cl.flags_in_order()) given[flag] = value;
    edit::check_edit_settings(kinds, given);
    std::vector<edit::EditStep> steps = recipe.steps;
    for (const auto& [flag, value] : cl.flags_in_order()) {
        if (std::optional<edit::EditStep> s = edit::edit_step_from_flag(kinds, flag, value, given)) steps.push_back(std::move(*s));
    }
    if (cl.has("--phi-cells")) {
        const double v = edit::flag_number("--phi-cells", cl.value("--phi-cells"));
        if (v != std::floor(v) || v < 0 || v > 4096) throw Error("--phi-cells", "expects a whole number in [0, 4096]");
        options.ndf.phi_cells = int(v);
    }
    if (cl.has("--svd")) {
        const std::string v = cl.value("--svd");
        if (v == "rank") options.ndf.recompress = edit::Recompress::KeepRank;
        else if (v == "ratio") options.ndf.recompress = edit::Recompress::KeptRatio;
        else throw Error("--svd", "'" + v + "' is not rank or ratio");
    }
    if (cl.has("--albedo-tolerance")) {
        options.albedo_tolerance = edit::flag_number("--albedo-tolerance", cl.value("--albedo-tolerance"));
        if (options.albedo_tolerance < 0.0) throw Error("--albedo-tolerance", "must not be negative");
    }
    if (cl.has("--no-albedo-check")) options.check_albedo = false;
    if (cl.has("--description")) options.description = cl.value("--description");
    if (steps.empty() && !cl.has("--recipe")) {
        throw Error("edit", "no edits given (flags or --recipe; configs/edits/identity.yaml is the identity)");
    }

    require_npf_texture(input, "");
    for (const edit::EditStep& s : steps) {
        if (s.kind == edit::EditStep::Kind::DiffuseMaterial || s.kind == edit::EditStep::Kind::SpecularMaterial)
            require_npf_texture(s.path, s.origin);
    }
    if (!dry) check_output_path(output);  // a destination that cannot be written fails now, not after the edits
    const NpfModel model = read_npf_texture(input);
    std::printf("%s: %s, %zu %s, D %d x %d, G %d x %d; %zu step%s\n", input.c_str(), model.isotropic() ? "isotropic" : "anisotropic",
                model.channel_count(), model.channels.is_rgb() ? "RGB channels" : "wavelengths", model.d_theta, model.d_phi,
                model.g_theta, model.g_phi, steps.size(), steps.size() == 1 ? "" : "s");
    std::fflush(stdout);
    // Only a long step reports progress (limit_albedo on a large anisotropic material): one bar
    // per step, on a terminal.
    std::unique_ptr<ProgressBar> bar;
    std::size_t step_index = 0;
    options.progress = [&](double f) {
        if (!bar) bar = std::make_unique<ProgressBar>("  [" + std::to_string(step_index + 1) + "] " + steps[step_index].label, true);
        bar->update(f);
    };
    const edit::EditResult result = edit::apply_edits(model, steps, options, [&](std::size_t i, const edit::EditRecord& r) {
        if (bar) bar->finish();
        bar.reset();
        step_index = i + 1;
        std::printf("  [%zu] %s\n      %s\n", i + 1, steps[i].label.c_str(), r.summary.c_str());
        std::fflush(stdout);
        for (const std::string& w : r.warnings) std::fprintf(stderr, "npf edit: warning: step %zu: %s\n", i + 1, w.c_str());
    });
    if (options.check_albedo) {
        std::printf("  directional albedo: largest %.4f (input %.4f)\n", result.output_albedo.max, result.input_albedo.max);
    }
    if (dry) {
        std::printf("dry run: nothing written\n");
        return 0;
    }
    write_npf_texture(result.model, output);
    if (result.history_keys.empty()) {
        std::printf("wrote %s (no steps)\n", output.c_str());
    } else {
        std::printf("wrote %s (history: %s to %s)\n", output.c_str(), result.history_keys.front().c_str(),
                    result.history_keys.back().c_str());
    }
    return 0;
}

}  // namespace npf::cli
