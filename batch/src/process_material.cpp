#include "material_context.h"

#include "material_hash.h"
#include "output_header.h"
#include "validation_renders.h"

#include <npf/batch/content_hash.h>
#include <npf/converter/convert.h>
#include <npf/core/error.h>
#include <npf/edit/recipe.h>
#include <npf/materials/open_material.h>
#include <npf/shading/npf_texture_file.h>
#include <npf/shading/npf_texture_layout.h>

#include <filesystem>
#include <memory>
#include <new>

namespace npf::batch::detail {

namespace fs = std::filesystem;

namespace {

// The material converted with its settings, edited when a recipe is named, and stamped with
// what the batch made it from.
NpfModel converted_model(const MaterialJob& job, const Brdf& source, bool isotropic, const std::string& hash, MaterialResult& r) {
    Conversion conversion = convert(source, resolve_convert_settings(job.settings, isotropic));
    NpfModel model = std::move(conversion.model);
    const auto e = job.settings.find("edit");
    if (e != job.settings.end() && !e->second.value.empty()) {
        const edit::EditRecipe recipe = edit::load_edit_recipe(e->second.value);
        model = edit::apply_edits(model, recipe.steps, recipe.options).model;
    }
    model.metadata.emplace_back(npf_exr::kMetaBatchName, job.name);
    model.metadata.emplace_back(npf_exr::kMetaBatchSettings, canonical_settings(job.settings));
    model.metadata.emplace_back(npf_exr::kMetaBatchHash, hash);
    const AwlsReport& fit = conversion.report.fit;
    if (fit.invalid_values > 0) r.reason = std::to_string(fit.invalid_values) + " invalid source values ignored";
    return model;
}

}  // namespace

std::string MaterialContext::publish(const std::string& name, const std::string& to, bool render) {
    if (in_worker) {
        moves.emplace_back(name, to);
        return staged(name);
    }
    publish_finished(*folders, name, to, render);
    return to;
}

std::uint64_t file_size(const std::string& path) {
    std::error_code ec;
    const auto n = fs::file_size(path, ec);
    return ec ? 0 : std::uint64_t(n);
}

std::string memory_note(std::uint64_t limit) { return limit ? "limit " + describe_memory(limit) : "no memory limit"; }

MaterialResult result_for(const MaterialJob& job, int shard) {
    MaterialResult r;
    r.name = job.name;
    r.input = job.input;
    r.output = job.output;
    r.shard = shard;
    return r;
}

MaterialResult process_material(const MaterialJob& job, MaterialContext& ctx) {
    std::error_code ec;
    MaterialResult r = result_for(job, ctx.shard);
    try {
        if (ctx.before_material) ctx.before_material(job.name, ctx.memory_limit);
        if (!fs::is_regular_file(job.input, ec)) {
            throw Error(job.input, fs::exists(job.input, ec) ? "not a regular file" : "no such file (named at " + job.origin + ")");
        }
        r.input_bytes = file_size(job.input);
        const std::unique_ptr<Brdf> source = open_material(job.input);
        r.input_bytes = source->info().file_bytes;  // 0 for analytic recipes: no ratio
        const bool isotropic = source->info().isotropic;
        r.hash = material_hash(job, isotropic);
        const RenderCheck check = resolve_render_check(job.settings);

        const auto header = header_of(job.output, true);
        const std::string hash_key = std::string(npf_exr::kMetadataPrefix) + npf_exr::kMetaBatchHash;
        const bool up_to_date = !ctx.force && header && header->count(hash_key) && header->at(hash_key) == r.hash;
        std::string render_hash;
        std::optional<std::vector<LightingCheck>> rendered;  // the renders there, when up to date
        if (check.enabled) {
            render_hash = render_hash_of(r.hash, check);
            rendered = renders_up_to_date(job, check, render_hash);
        }
        const bool render_up_to_date = !check.enabled || (up_to_date && rendered);

        std::string output = job.output;  // where the output is read from below
        if (!up_to_date) {
            const NpfModel model = converted_model(job, *source, isotropic, r.hash, r);
            const std::string final_name = job.name + ".exr";
            write_npf_texture(model, ctx.staged(final_name));  // no time stamp: the bytes are the content's
            output = ctx.publish(final_name, job.output, false);
            fill_recorded_figures(r, model.metadata);  // what was just written, from memory
            r.status = MaterialStatus::Converted;
        } else {
            // Made by an earlier run: its figures are the ones its header records.
            fill_recorded_figures(r, *header);
            r.status = MaterialStatus::Skipped;
        }
        r.output_bytes = file_size(output);

        if (check.enabled && !render_up_to_date) {
            render_and_compare(job, *source, output, check, render_hash, ctx, r);
            if (r.status == MaterialStatus::Skipped) r.reason = "validation render redone";
        } else if (check.enabled && rendered) {
            r.lightings = *rendered;
            r.judge_by_worst_lighting();
        }
    } catch (const std::bad_alloc&) {
        r.status = MaterialStatus::Failed;
        r.reason = job.input + ": ran out of memory (" + memory_note(ctx.memory_limit) + ")";
    } catch (const Error& e) {
        r.status = MaterialStatus::Failed;
        r.reason = ctx.stage->shown(e.what());
    } catch (const std::exception& e) {
        r.status = MaterialStatus::Failed;
        r.reason = job.input + ": internal error: " + ctx.stage->shown(e.what());
    }
    return r;
}

}  // namespace npf::batch::detail
