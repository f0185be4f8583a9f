// npf edit: edits on a fitted NPF material (paper sec. 4.3; docs/editing.md): NDF transforms,
// diffuse and specular colour swaps, thin-film Fresnel. Steps come from a YAML recipe and from
// flags (recipe first, then the flags in command-line order), both through the edit kinds
// (npf/edit/edit_kinds.h), which also give the edit flags and their help.
#include "command_line.h"
#include "commands.h"
#include "file_uses.h"
#include "progress.h"

#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/edit/edit_request.h>
#include <npf/shading/npf_texture_file.h>

#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace npf::cli {

namespace {

// The edit flags (edit_request.h), between the command's own.
const std::vector<FlagSpec>& edit_flags() {
    static const std::vector<FlagSpec> flags = [] {
        std::vector<FlagSpec> f = flag_table({
            "-o VALUE  output factor texture (.exr); required unless --dry-run",
            "--recipe VALUE  YAML recipe: a list of steps applied in order (configs/edits/)",
        });
        for (const edit::EditRunFlag& e : edit::edit_run_flags()) f.push_back({e.name, e.takes_value, e.help});
        f.push_back({"--dry-run", false, "apply and report, write nothing"});
        return f;
    }();
    return flags;
}

const char* kHelp =
    "usage: npf edit IN.exr -o OUT.exr [--recipe FILE.yaml] [edit flags]\n\n"
    "Edits a fitted NPF material (paper sec. 4.3): NDF linear transforms and their friendly forms,\n"
    "diffuse colour, specular colour, thin-film Fresnel. The recipe's steps run first, then the edit\n"
    "flags in the order given; each step's record goes into the file's metadata (edit_001, ...), which\n"
    "npf info shows. After each step the directional albedo is checked (a warning above 1).\n"
    "Conventions, maths and limits: docs/editing.md; example recipes: configs/edits/. Examples:\n"
    "  npf edit copper.exr -o copper_wide.exr --stretch-tangent 2 --rotate 30\n"
    "  npf edit felt.exr -o felt_red.exr --diffuse-srgb 0.8,0.1,0.1\n"
    "  npf edit steel.exr -o steel_film.exr --thin-film 615,1.3 --film-base fitted\n"
    "  npf edit paper.exr -o paper_capped.exr --limit-albedo 1\n\n";

bool is_command_flag(const std::string& flag) {
    return flag == "-o" || flag == "--recipe" || flag == "--dry-run" || flag == "--help";
}

}  // namespace

int run_edit(const std::vector<std::string>& args) {
    const CommandLine cl = read_command_line(kHelp, edit_flags(), args);
    const bool dry = cl.has("--dry-run");
    cl.expect_positional(1, 1, "one IN.exr");
    if (!dry) cl.require("-o");
    const std::string input = cl.positional()[0], output = cl.value("-o");

    // Everything that can fail on the command line fails before any work.
    std::vector<std::pair<std::string, std::string>> given;
    for (const auto& [flag, value] : cl.flags_in_order()) {
        if (!is_command_flag(flag)) given.emplace_back(flag, value);
    }
    edit::EditRequest request = edit::edit_request(cl.has("--recipe") ? cl.value("--recipe") : std::string(), given);
    const std::vector<edit::EditStep>& steps = request.steps;
    edit::EditOptions& options = request.options;
    edit::require_npf_textures(input, request);
    if (!dry) {
        FileUses uses;
        uses.input(input, "the input");
        if (cl.has("--recipe")) uses.input(cl.value("--recipe"), "--recipe");
        for (const auto& [flag, value] : given) uses.input(value, flag);  // flags that name files (materials, spectra)
        uses.output(output, "-o").check();
        check_output_path(output);  // a destination that cannot be written fails now, not after the edits
    }
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
