#include "validation_renders.h"

#include "output_header.h"

#include <npf/core/atomic_file.h>
#include <npf/materials/open_material.h>
#include <npf/render/paired_render.h>
#include <npf/render/render_output.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>

namespace npf::batch::detail {

namespace fs = std::filesystem;

namespace {

// A lighting's part of a render's file name: a built-in name as it is, a map file's stem with
// anything but letters, digits, '-' and '_' as '_' (two maps of one stem are two uses of one
// file name, refused by check_batch_files).
std::string lighting_tag(const std::string& lighting) {
    const std::vector<std::string>& names = render::builtin_lighting_names();
    if (std::find(names.begin(), names.end(), lighting) != names.end()) return lighting;
    std::string tag = fs::path(lighting).stem().string();
    for (char& c : tag)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
    return tag.empty() ? "map" : tag;
}

// A validation render is the batch's own file: read only when it is a regular file at its name
// (a link there is not taken for it; publishing refuses it).
bool own_regular_file(const std::string& path) {
    std::error_code ec;
    return fs::symlink_status(path, ec).type() == fs::file_type::regular;
}

const render::Lighting& lighting_named(MaterialContext& ctx, const std::string& name) {
    auto it = ctx.environments.find(name);
    if (it == ctx.environments.end()) it = ctx.environments.emplace(name, render::make_lighting(name, "render.env")).first;
    return it->second;
}

// Staged as the batch's own file: a link at the name is refused.
void stage_render(const MaterialContext& ctx, const std::string& file, const render::RenderResult& image,
                  const render::RenderMetadata& meta) {
    AtomicOutput staged(ctx.staged(file), OutputOptions{kOwner, ctx.stage->path_of(file)});
    render::write_render_exr(staged, image, meta);
    staged.commit();
}

}  // namespace

std::string render_file(const MaterialJob& job, const std::string& lighting, const char* kind) {
    const fs::path out(job.output);
    return (out.parent_path() / "renders" / (out.stem().string() + "." + lighting_tag(lighting) + "." + kind + ".exr")).string();
}

std::optional<std::vector<LightingCheck>> renders_up_to_date(const MaterialJob& job, const RenderCheck& check,
                                                             const std::string& render_hash) {
    std::vector<LightingCheck> checks;
    for (const std::string& l : check.lightings) {
        const std::string path = render_file(job, l, "npf");
        if (!own_regular_file(path) || !own_regular_file(render_file(job, l, "reference"))) return std::nullopt;
        const auto header = header_of(path, false);
        if (!header || !header->count("npf:batch_hash") || header->at("npf:batch_hash") != render_hash) return std::nullopt;
        checks.push_back(lighting_check_of(render::lighting_label(l), *header));
    }
    return checks;
}

void render_and_compare(const MaterialJob& job, const Brdf& source, const std::string& output, const RenderCheck& check,
                        const std::string& render_hash, MaterialContext& ctx, MaterialResult& r) {
    // The output as written (read back from its file): what the renders validate is the file.
    const std::unique_ptr<Brdf> fitted = open_material(output);
    render::PairedRenderSettings settings;
    settings.size = check.size;
    settings.spp = check.spp;
    settings.seed = check.seed;
    settings.threads = check.threads;
    settings.test_name = "npf";
    r.lightings.clear();
    for (const std::string& name : check.lightings) {
        const render::PairedReference pair(source, lighting_named(ctx, name), settings);
        const render::PairedComparison c = pair.compare(*fitted);
        const LightingCheck figures{pair.lighting().label(), c.metrics.psnr, c.floor_psnr, c.metrics.ssim, c.metrics.relmse};
        r.lightings.push_back(figures);
        const render::RenderOptions options = pair.options();
        render::RenderMetadata ref_meta = render::describe_render(pair.reference(), options, pair.lighting());
        ref_meta.insert(ref_meta.begin(), {"npf:material", job.input});
        ref_meta.emplace_back("npf:batch_hash", render_hash);
        render::RenderMetadata npf_meta = render::describe_render(c.test, options, pair.lighting());
        npf_meta.insert(npf_meta.begin(), {"npf:material", job.output});
        npf_meta.emplace_back("npf:batch_hash", render_hash);
        for (auto& entry : render_figures_metadata(figures)) npf_meta.push_back(std::move(entry));
        const std::string tag = lighting_tag(name);
        const std::string ref_name = job.name + "." + tag + ".reference.exr", npf_name = job.name + "." + tag + ".npf.exr";
        stage_render(ctx, ref_name, pair.reference(), ref_meta);
        stage_render(ctx, npf_name, c.test, npf_meta);
        ctx.publish(ref_name, render_file(job, name, "reference"), true);
        ctx.publish(npf_name, render_file(job, name, "npf"), true);  // last: its hash says the pair is done
    }
    r.judge_by_worst_lighting();
}

}  // namespace npf::batch::detail
