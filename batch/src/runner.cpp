#include <npf/batch/runner.h>

#include "worker_process.h"

#include <npf/batch/content_hash.h>
#include <npf/core/atomic_file.h>
#include <npf/core/file_identity.h>
#include <npf/core/owned_folder.h>
#include <npf/core/text_input.h>
#include <npf/converter/convert.h>
#include <npf/converter/convert_settings_table.h>
#include <npf/materials/open_material.h>
#include <npf/materials/yaml_context.h>
#include <npf/core/error.h>
#include <npf/core/version.h>
#include <npf/core/text.h>
#include <npf/edit/recipe.h>
#include <npf/render/default_environment.h>
#include <npf/render/environment_map.h>
#include <npf/render/image_metrics.h>
#include <npf/render/lighting.h>
#include <npf/render/path_tracer.h>
#include <npf/render/render_output.h>
#include <npf/shading/npf_texture_file.h>
#include <npf/shading/npf_texture_layout.h>

#include <OpenImageIO/imageio.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <tuple>

#include <ctime>
#include <csignal>
#include <new>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>


namespace npf::batch {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The recipe's bytes and those of every file a value in it names (materials, spectra), so that
// changing a referenced file redoes the edit.
std::string edit_hash_text(const std::string& recipe) {
    std::string t = "edit " + sha256_file(recipe) + "\n";
    for (const auto& [name, path] : files_named_in_yaml(recipe)) t += "edit-file " + name + " " + sha256_file(path) + "\n";
    return t;
}

std::uint64_t file_size(const std::string& path) {
    std::error_code ec;
    const auto n = fs::file_size(path, ec);
    return ec ? 0 : std::uint64_t(n);
}

// The first part's header attributes of an OpenEXR file, as strings; nothing when the file is
// missing or unreadable (headers only: cheap).
std::optional<std::map<std::string, std::string>> header_of(const std::string& path, bool npf_texture) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return std::nullopt;
    // Outputs are NPF textures: sniffed first (its header checks keep a damaged file at an
    // output's name from reaching OpenImageIO's assertions); renders are the batch's own.
    if (npf_texture && !is_npf_texture(path)) return std::nullopt;
    // The OpenEXR reader whatever the name says (OpenImageIO would choose by the extension).
    auto in = OIIO::ImageInput::create("openexr");
    OIIO::ImageSpec spec;
    if (!in || !in->open(path, spec)) {
        OIIO::geterror();  // clear it
        return std::nullopt;
    }
    std::map<std::string, std::string> out;
    for (const OIIO::ParamValue& p : in->spec().extra_attribs) {
        if (p.type() == OIIO::TypeString) out[p.name().string()] = p.get_string();
    }
    in->close();
    return out;
}

std::optional<double> attr_number(const std::map<std::string, std::string>& h, const std::string& key) {
    const auto it = h.find(key);
    if (it == h.end()) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (end == it->second.c_str()) return std::nullopt;
    return v;
}

void fill_from_header(MaterialResult& r, const std::map<std::string, std::string>& h) {
    const std::string m = npf_exr::kMetadataPrefix;
    r.error_mean = attr_number(h, m + npf_exr::kMetaErrorMean);
    r.error_max = attr_number(h, m + npf_exr::kMetaErrorMax);
    r.fitted_error_mean = attr_number(h, m + npf_exr::kMetaFittedErrorMean);
    r.fitted_error_max = attr_number(h, m + npf_exr::kMetaFittedErrorMax);
    r.albedo_max = attr_number(h, m + npf_exr::kMetaAlbedoMax);
    r.edits.clear();
    for (int k = 1; k < 1000; ++k) {
        char key[32];
        std::snprintf(key, sizeof key, "%s%03d", npf_exr::kMetaEditPrefix, k);
        const auto it = h.find(m + key);
        if (it == h.end()) break;
        r.edits.push_back(first_line(it->second));
    }
}

// One lighting's figures, from its npf render's header (a figure that is not there: infinite
// PSNR and floor, as a pair that agrees exactly).
LightingCheck lighting_check_of(const std::string& label, const std::map<std::string, std::string>& h) {
    const double inf = std::numeric_limits<double>::infinity();
    return {label, attr_number(h, "npf:batch_psnr").value_or(inf), attr_number(h, "npf:batch_psnr_floor").value_or(inf),
            attr_number(h, "npf:batch_ssim").value_or(1.0), attr_number(h, "npf:batch_relmse").value_or(0.0)};
}

// The tool named in messages about the places it owns.
constexpr const char* kOwner = "npf batch";

std::string shard_tag(const Shard& s) { return "shard-" + std::to_string(s.index) + "-of-" + std::to_string(s.count); }

// Holds an exclusive lock on a file for the lifetime of the object (released by the kernel if
// the process dies). The file is the batch's own: made in its work folder, never through a link.
class FileLock {
public:
    FileLock(const OwnedFolder& folder, const std::string& name) : m_fd(folder.open_file(name, true)) {
        if (::flock(m_fd, LOCK_EX | LOCK_NB) != 0) {
            ::close(m_fd);
            throw Error(folder.path_of(name), "another npf batch is running this shard in this output folder (the lock is held)");
        }
    }
    ~FileLock() { ::close(m_fd); }
    FileLock(const FileLock&) = delete;
    FileLock& operator=(const FileLock&) = delete;

private:
    int m_fd = -1;
};

// The places a run works in: the output folder (the user's: a link to it is followed), and the
// batch's own, never reached through a link (owned_folder.h): `.npf-batch`, the shard's lock and
// stage folder (mode 0700: nobody else plants anything in it), `renders/` when first needed.
class BatchFolders {
public:
    BatchFolders(const std::string& output_dir, const Shard& shard)
        : m_output(OwnedFolder::user_folder(output_dir, kOwner, true)), m_work(m_output.owned_child(".npf-batch")),
          m_lock(m_work, shard_tag(shard) + ".lock"), m_stage(m_work.owned_child(shard_tag(shard), 0700)) {
        m_stage.clear();  // what a killed run left
    }
    const OwnedFolder& stage() const { return m_stage; }
    // Refuses a link or a file at `renders` before any work (it is made when first needed).
    void check_renders() const { m_output.check_owned_child("renders"); }
    const OwnedFolder& renders() {
        if (!m_renders) m_renders.emplace(m_output.owned_child("renders"));
        return *m_renders;
    }

private:
    OwnedFolder m_output, m_work;
    FileLock m_lock;
    OwnedFolder m_stage;
    std::optional<OwnedFolder> m_renders;
};

std::string file_name(const std::string& path) { return fs::path(path).filename().string(); }

// The staged file `name` to its place `to`, by the rules every npf output follows (atomic_file.h):
// at an output's name a link is followed, a FIFO written through, a folder refused, the bytes
// synced before the name changes; a validation render is the batch's own file in its own
// `renders/` folder, where a link is refused.
void publish_finished(BatchFolders& folders, const std::string& name, const std::string& to, bool render) {
    const OwnedFolder& stage = folders.stage();
    try {
        if (render) {
            const OwnedFolder& renders = folders.renders();
            const std::string file = file_name(to);
            publish_staged_file(stage.through(name), renders.through(file), OutputOptions{kOwner, renders.path_of(file)});
        } else {
            publish_staged_file(stage.through(name), to);
        }
    } catch (const Error& e) {
        throw Error(stage.shown(e.source()), stage.shown(e.problem()));
    }
}

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

// renders/NAME.LIGHTING.reference.exr and .npf.exr beside the output.
std::string render_file(const MaterialJob& job, const std::string& lighting, const char* kind) {
    const fs::path out(job.output);
    return (out.parent_path() / "renders" / (out.stem().string() + "." + lighting_tag(lighting) + "." + kind + ".exr")).string();
}

std::string fmt(const char* format, double v) {
    char b[64];
    std::snprintf(b, sizeof b, format, v);
    return b;
}

bool ends_with(const std::string& s, const char* tail) {
    const std::size_t n = std::strlen(tail);
    return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

std::string hash_text(const MaterialJob& job, bool source_isotropic, const std::string& input_sha) {
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

// The hash every validation render of a material is stamped with: the material's, the render
// settings and each lighting (a map by its bytes; a built-in one by its name: its geometry is
// this build's, and the material hash names the build).
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

// How a material is processed: in this process, or in a worker whose finished files the parent
// moves into place (so that a worker killed at any point publishes nothing). Files are staged
// under names in the stage folder, reached through its descriptor.
struct MaterialContext {
    const OwnedFolder* stage = nullptr;
    BatchFolders* folders = nullptr;  // in the batch's own process: publishes at once
    bool force = false;
    int shard = 0;
    bool in_worker = false;
    std::uint64_t memory_limit = 0;  // the worker's, for messages
    std::map<std::string, render::Lighting> environments;
    std::vector<std::pair<std::string, std::string>> moves;  // worker: (staged name, final), in order

    std::string staged(const std::string& name) const { return stage->through(name); }
    // Where the finished file is to be read from afterwards.
    std::string publish(const std::string& name, const std::string& to, bool render) {
        if (in_worker) {
            moves.emplace_back(name, to);
            return staged(name);
        }
        publish_finished(*folders, name, to, render);
        return to;
    }
};

std::string memory_note(std::uint64_t limit) { return limit ? "limit " + describe_memory(limit) : "no memory limit"; }

// Test-only (docs/batch.md "Failure isolation"): NPF_TEST_FAULT=KIND:NAME[,KIND:NAME...] makes
// material NAME fail the way a broken reader can (abort, segv, oom, hang, kill, exit), so that
// the tests can show that the batch survives it. In a worker only, but for `oom`, which in this
// process throws std::bad_alloc (the rest would end the caller's process).
void apply_test_fault(const std::string& name, const MaterialContext& ctx) {
    const char* env = std::getenv("NPF_TEST_FAULT");
    if (!env) return;
    const std::string spec = env;
    for (std::size_t at = 0; at <= spec.size();) {
        const std::size_t comma = std::min(spec.find(',', at), spec.size());
        const std::string item = spec.substr(at, comma - at);
        at = comma + 1;
        const std::size_t colon = item.find(':');
        if (colon == std::string::npos || item.substr(colon + 1) != name) continue;
        const std::string kind = item.substr(0, colon);
        if (kind == "oom") {
            if (!ctx.in_worker || ctx.memory_limit == 0) throw std::bad_alloc();
            // Memory until the limit refuses it (RLIMIT_DATA counts it untouched).
            std::vector<void*> blocks;
            const std::size_t block = std::size_t(64) << 20;
            try {
                for (std::uint64_t total = 0; total <= ctx.memory_limit; total += block) blocks.push_back(::operator new(block));
            } catch (...) {
                for (void* b : blocks) ::operator delete(b);
                throw;
            }
            for (void* b : blocks) ::operator delete(b);
            throw std::bad_alloc();
        }
        if (!ctx.in_worker) continue;
        const struct rlimit no_core {0, 0};
        ::setrlimit(RLIMIT_CORE, &no_core);  // no core files from a test
        if (kind == "abort") std::abort();
        if (kind == "segv") {
            std::signal(SIGSEGV, SIG_DFL);
            std::raise(SIGSEGV);
        }
        if (kind == "kill") std::raise(SIGKILL);
        if (kind == "exit") std::_Exit(9);
        if (kind == "hang") {
            for (;;) ::pause();
        }
    }
}

// A result for the job with what every path knows of it: names, paths, shard.
MaterialResult result_for(const MaterialJob& job, int shard) {
    MaterialResult r;
    r.name = job.name;
    r.input = job.input;
    r.output = job.output;
    r.shard = shard;
    return r;
}

// A validation render is the batch's own file: read only when it is a regular file at its name
// (a link there is not taken for it; publishing refuses it).
bool own_regular_file(const std::string& path) {
    std::error_code ec;
    return fs::symlink_status(path, ec).type() == fs::file_type::regular;
}

// The figures of the material's validation renders when every lighting's pair is there and
// stamped with `render_hash`; nothing when any is missing or older.
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

// Renders the source and its output (`output`, where it can be read now) under each lighting of
// `check`, paired (docs/metrics.md sec. 5): maps with environment sampling only at one seed, so
// both images are estimated at the same light directions, the pair again at the next seed for
// the PSNR's noise floor; directional lights once, with no noise. Publishes each lighting's
// renders, stamped with `render_hash`, and fills the result's metrics (the worst lighting's).
void render_and_compare(const MaterialJob& job, const Brdf& source, const std::string& output, const RenderCheck& check,
                        const std::string& render_hash, MaterialContext& ctx, MaterialResult& r) {
    const std::unique_ptr<Brdf> fitted = open_material(output);
    r.lightings.clear();
    for (const std::string& name : check.lightings) {
        auto it = ctx.environments.find(name);
        if (it == ctx.environments.end()) it = ctx.environments.emplace(name, render::make_lighting(name, "render.env")).first;
        const render::Lighting& lighting = it->second;
        render::RenderOptions ro;
        ro.width = ro.height = check.size;
        ro.spp = check.spp * lighting.spp_factor;  // as the prediction: more where the floor is near
        ro.seed = check.seed;
        ro.threads = check.threads;
        ro.sampling = render::Sampling::Environment;
        const render::RenderResult reference = render::render(source, lighting, ro);
        const render::RenderResult test = render::render(*fitted, lighting, ro);
        const render::ImageMetrics metrics = render::compare_images(reference.image, test.image, {}, "reference", "npf");
        double floor = std::numeric_limits<double>::infinity();  // directional: no samples, no noise
        if (!lighting.directional()) {
            render::RenderOptions ro2 = ro;
            ro2.seed = render::noise_floor_seed(check.seed);
            floor = render::paired_noise_floor(reference.image, test.image, render::render(source, lighting, ro2).image,
                                               render::render(*fitted, lighting, ro2).image, {}, "reference", "npf")
                        .psnr;
        }
        r.lightings.push_back({lighting.label(), metrics.psnr, floor, metrics.ssim, metrics.relmse});
        render::RenderMetadata ref_meta = render::describe_render(reference, ro, lighting);
        ref_meta.insert(ref_meta.begin(), {"npf:material", job.input});
        ref_meta.emplace_back("npf:batch_hash", render_hash);
        render::RenderMetadata npf_meta = render::describe_render(test, ro, lighting);
        npf_meta.insert(npf_meta.begin(), {"npf:material", job.output});
        npf_meta.emplace_back("npf:batch_hash", render_hash);
        npf_meta.emplace_back("npf:batch_psnr", fmt("%.9g", metrics.psnr));
        npf_meta.emplace_back("npf:batch_psnr_floor", fmt("%.9g", floor));
        npf_meta.emplace_back("npf:batch_ssim", fmt("%.9g", metrics.ssim));
        npf_meta.emplace_back("npf:batch_relmse", fmt("%.9g", metrics.relmse));
        const std::string tag = lighting_tag(name);
        const std::string ref_name = job.name + "." + tag + ".reference.exr", npf_name = job.name + "." + tag + ".npf.exr";
        // Staged as the batch's own files: a link at the name is refused.
        const auto stage = [&ctx](const std::string& file, const render::RenderResult& image, const render::RenderMetadata& meta) {
            AtomicOutput staged(ctx.staged(file), OutputOptions{kOwner, ctx.stage->path_of(file)});
            render::write_render_exr(staged, image, meta);
            staged.commit();
        };
        stage(ref_name, reference, ref_meta);
        stage(npf_name, test, npf_meta);
        ctx.publish(ref_name, render_file(job, name, "reference"), true);
        ctx.publish(npf_name, render_file(job, name, "npf"), true);  // last: its hash says the pair is done
    }
    r.judge_by_worst_lighting();
}

// One material: checked against its output's hash, converted, edited, stamped, written, and
// rendered when asked; every problem becomes its failed status and reason.
MaterialResult process_material(const MaterialJob& job, MaterialContext& ctx) {
    std::error_code ec;
    MaterialResult r = result_for(job, ctx.shard);
    const std::string final_name = job.name + ".exr";
    try {
        apply_test_fault(job.name, ctx);
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
        const std::string m = npf_exr::kMetadataPrefix;
        const bool up_to_date = !ctx.force && header && header->count(m + npf_exr::kMetaBatchHash) &&
                                header->at(m + npf_exr::kMetaBatchHash) == r.hash;
        std::string render_hash;
        std::optional<std::vector<LightingCheck>> rendered;  // the renders there, when up to date
        if (check.enabled) {
            render_hash = render_hash_of(r.hash, check);
            rendered = renders_up_to_date(job, check, render_hash);
        }
        const bool render_up_to_date = !check.enabled || (up_to_date && rendered);

        std::string output = job.output;  // where the output is read from below
        if (!up_to_date) {
            ConvertSettings s = resolve_convert_settings(job.settings, isotropic);
            Conversion conversion = convert(*source, s);
            const ConvertReport& rep = conversion.report;
            NpfModel model = std::move(conversion.model);
            const auto e = job.settings.find("edit");
            if (e != job.settings.end() && !e->second.value.empty()) {
                const edit::EditRecipe recipe = edit::load_edit_recipe(e->second.value);
                edit::EditResult edited = edit::apply_edits(model, recipe.steps, recipe.options);
                model = std::move(edited.model);
            }
            model.metadata.emplace_back(npf_exr::kMetaBatchName, job.name);
            model.metadata.emplace_back(npf_exr::kMetaBatchSettings, canonical_settings(job.settings));
            model.metadata.emplace_back(npf_exr::kMetaBatchHash, r.hash);
            write_npf_texture(model, ctx.staged(final_name));  // no time stamp: the bytes are the content's
            output = ctx.publish(final_name, job.output, false);
            if (rep.fit.invalid_values > 0) r.reason = std::to_string(rep.fit.invalid_values) + " invalid source values ignored";
            r.status = MaterialStatus::Converted;
        } else {
            r.status = MaterialStatus::Skipped;
        }
        r.output_bytes = file_size(output);
        if (const auto h = header_of(output, true)) fill_from_header(r, *h);

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

// The parent's check before it starts a worker: whether the output (and its renders) are up to
// date, from the input's bytes and the output's header alone. The input is not opened as a
// material (a reader that crashes must crash in a worker), so its isotropy is unknown: the
// output is up to date when its hash is the one for either isotropy, which for the same input
// bytes and npf version only the real one can have produced. Nothing: leave it to the worker.
std::optional<MaterialResult> up_to_date_result(const MaterialJob& job, int shard) {
    try {
        std::error_code ec;
        if (!fs::is_regular_file(job.input, ec)) return std::nullopt;
        const auto header = header_of(job.output, true);
        const std::string key = std::string(npf_exr::kMetadataPrefix) + npf_exr::kMetaBatchHash;
        if (!header || !header->count(key)) return std::nullopt;
        const std::string input_sha = sha256_file(job.input);
        const std::string& stored = header->at(key);
        if (stored != hash_text(job, true, input_sha) && stored != hash_text(job, false, input_sha)) return std::nullopt;
        MaterialResult r = result_for(job, shard);
        r.status = MaterialStatus::Skipped;
        r.hash = stored;
        const RenderCheck check = resolve_render_check(job.settings);
        if (check.enabled) {
            const auto rendered = renders_up_to_date(job, check, render_hash_of(stored, check));
            if (!rendered) return std::nullopt;
            r.lightings = *rendered;
            r.judge_by_worst_lighting();
        }
        // As open_material's file_bytes: 0 for an analytic recipe (chosen by its name).
        r.input_bytes = ends_with(job.input, ".yaml") || ends_with(job.input, ".yml") ? 0 : file_size(job.input);
        r.output_bytes = file_size(job.output);
        fill_from_header(r, *header);
        return r;
    } catch (const std::exception&) {
        return std::nullopt;  // the worker reports it
    }
}

// The job file a worker reads (YAML): the material, the stage folder (with its device and inode,
// so that the worker uses the very folder the batch made) and the names its answers get there.
std::string job_text(const MaterialJob& job, const MaterialContext& ctx, const std::string& result, const std::string& moves) {
    YAML::Emitter out;
    // Quoted, so that no text reads back as null, a number or a boolean.
    const auto q = [&out](const std::string& text) { out << YAML::DoubleQuoted << text; };
    out << YAML::BeginMap;
    out << YAML::Key << "npf_batch_worker_job" << YAML::Value << 2;
    out << YAML::Key << "parent" << YAML::Value << long(::getpid());
    out << YAML::Key << "name" << YAML::Value;
    q(job.name);
    out << YAML::Key << "input" << YAML::Value;
    q(job.input);
    out << YAML::Key << "output" << YAML::Value;
    q(job.output);
    out << YAML::Key << "origin" << YAML::Value;
    q(job.origin);
    out << YAML::Key << "stage" << YAML::Value;
    q(ctx.stage->path());
    out << YAML::Key << "stage_device" << YAML::Value << std::to_string(ctx.stage->device());
    out << YAML::Key << "stage_inode" << YAML::Value << std::to_string(ctx.stage->inode());
    out << YAML::Key << "force" << YAML::Value << ctx.force;
    out << YAML::Key << "shard" << YAML::Value << ctx.shard;
    out << YAML::Key << "memory_limit" << YAML::Value << std::to_string(ctx.memory_limit);
    out << YAML::Key << "result" << YAML::Value;
    q(result);
    out << YAML::Key << "moves" << YAML::Value;
    q(moves);
    out << YAML::Key << "settings" << YAML::Value << YAML::BeginMap;
    for (const auto& [k, v] : job.settings) {
        out << YAML::Key << k << YAML::Value << YAML::Flow << YAML::BeginSeq;
        q(v.value);
        q(v.origin);
        out << YAML::EndSeq;
    }
    out << YAML::EndMap << YAML::EndMap;
    return std::string(out.c_str()) + "\n";
}

// Why a worker that did not answer ended, as a material's failure: "PATH: killed by signal 11
// (segmentation fault) (its last words: ...)".
std::string worker_failure(const MaterialJob& job, const detail::WorkerEnd& end, const MaterialLimits& limits,
                           const std::string& executable, const std::string& tail) {
    const std::string said = tail.empty() ? "" : " (its last words: " + tail + ")";
    if (!end.start_error.empty()) return "cannot start the worker process " + executable + ": " + end.start_error;
    if (end.timed_out) return job.input + ": took longer than " + describe_seconds(limits.seconds) + " (time_limit), stopped";
    if (end.signal > 0) {
        if (tail.find("bad_alloc") != std::string::npos)
            return job.input + ": ran out of memory (" + memory_note(limits.memory_bytes) + "), " + detail::signal_text(end.signal);
        std::string reason = job.input + ": killed by " + detail::signal_text(end.signal);
        if (end.signal == SIGKILL)
            reason += " from outside, at " + describe_memory(std::uint64_t(end.peak_resident_bytes)) +
                      " resident (the system's out-of-memory killer?)";
        return reason + said;
    }
    if (end.exited && end.exit_code != 0)
        return job.input + ": the worker process exited with status " + std::to_string(end.exit_code) + said;
    return "";
}

// The worker's answer and the files it finished, read from the stage (never through a link) and
// published; a list naming anything but this material's output and renders is refused.
MaterialResult take_answer(const MaterialJob& job, BatchFolders& folders, const std::string& result, const std::string& moves) {
    const OwnedFolder& stage = folders.stage();
    const BatchSummary answer =
        parse_summary_json(stage.read_text(result, "a batch worker's answer", kConfigTextBounds), stage.path_of(result));
    const YAML::Node list = YAML::Load(stage.read_text(moves, "a batch worker's list of finished files", kConfigTextBounds));
    std::vector<std::tuple<std::string, std::string, bool>> to_move;  // staged name, final, a render
    for (const YAML::Node& m : list) {
        const std::string name = m[0].as<std::string>(), to = m[1].as<std::string>();
        const RenderCheck check = resolve_render_check(job.settings);
        bool render = false;
        for (const std::string& l : check.lightings)
            render = render || to == render_file(job, l, "reference") || to == render_file(job, l, "npf");
        if ((to != job.output && !render) || name.empty() || name.find('/') != std::string::npos)
            throw Error(stage.path_of(moves), "lists a file that is not one of this material's: " + name + " -> " + to);
        to_move.emplace_back(name, to, render);
    }
    if (answer.materials.size() != 1 || answer.materials[0].name != job.name)
        throw Error(stage.path_of(result), "the worker process answered for another material");
    MaterialResult r = answer.materials[0];
    try {
        for (const auto& [name, to, render] : to_move) publish_finished(folders, name, to, render);
    } catch (const Error& e) {
        r.status = MaterialStatus::Failed;
        r.reason = e.what();
    }
    return r;
}

// Runs one material in a worker process under its limits and turns however it ended into a
// result: the worker's own, or a failure naming the input and why (signal, limit, exit status).
// Nothing when options.stop ended it: the material was cut short, not done.
std::optional<MaterialResult> run_in_worker(const MaterialJob& job, BatchFolders& folders, const BatchOptions& options) {
    const int shard = options.shard.index;
    MaterialResult failed = result_for(job, shard);
    failed.status = MaterialStatus::Failed;
    MaterialLimits limits;
    try {
        limits = resolve_limits(job.settings);
    } catch (const Error& e) {
        failed.reason = e.what();
        return failed;
    }
    if (!options.force) {
        if (std::optional<MaterialResult> skipped = up_to_date_result(job, shard)) return *skipped;
    }
    const OwnedFolder& stage = folders.stage();
    MaterialContext ctx;
    ctx.stage = &stage;
    ctx.force = options.force;
    ctx.shard = shard;
    ctx.memory_limit = limits.memory_bytes;
    const std::string job_file = job.name + ".job.yaml", result = job.name + ".result.json", moves = job.name + ".moves.yaml";
    int log = -1;
    try {
        stage.write_new_file(job_file, job_text(job, ctx, result, moves));
        log = stage.create_file(job.name + ".worker.log", 0644);
    } catch (const Error& e) {
        failed.reason = e.what();
        return failed;
    }
    // The worker is told the job's path as people read it; it checks that the folder it finds
    // there is this one (device and inode in the job).
    const detail::WorkerEnd end = detail::run_worker_process(options.worker_executable, {"batch", "--worker", stage.path_of(job_file)},
                                                             log, limits.seconds, options.stop);
    const std::string tail = detail::last_line(log);
    ::close(log);
    if (end.stopped || (options.stop && *options.stop)) return std::nullopt;
    failed.reason = worker_failure(job, end, limits, options.worker_executable, tail);
    if (!failed.reason.empty()) return failed;
    // Ended normally (or its status was lost): its answer, and the files it finished.
    try {
        return take_answer(job, folders, result, moves);
    } catch (const std::exception& e) {
        const std::string said = tail.empty() ? "" : " (its last words: " + tail + ")";
        failed.reason = job.input + ": the worker process ended without an answer (" + std::string(e.what()) + ")" + said;
        return failed;
    }
}

}  // namespace

Shard parse_shard(const std::string& text, const std::string& what) {
    const std::size_t slash = text.find('/');
    const auto whole = [&](const std::string& v) -> long {
        if (v.empty() || v.size() > 6 || v.find_first_not_of("0123456789") != std::string::npos)
            throw Error(what, "expects K/N with whole numbers 0 <= K < N, got '" + text + "'");
        return std::atol(v.c_str());
    };
    if (slash == std::string::npos) throw Error(what, "expects K/N (shard K of N, from 0), got '" + text + "'");
    const long k = whole(text.substr(0, slash)), n = whole(text.substr(slash + 1));
    if (n < 1 || n > 100000 || k >= n) throw Error(what, "expects K/N with 0 <= K < N <= 100000, got '" + text + "'");
    return Shard{int(k), int(n)};
}

std::vector<std::size_t> shard_members(std::size_t count, const Shard& shard) {
    std::vector<std::size_t> out;
    for (std::size_t i = std::size_t(shard.index); i < count; i += std::size_t(shard.count)) out.push_back(i);
    return out;
}

std::string summary_base(const BatchConfig& config, const Shard& shard) {
    std::string base = config.summary.empty() ? (fs::path(config.output_dir) / "batch-summary").string() : config.summary;
    if (shard.count > 1) base += "." + shard_tag(shard);
    return base;
}

void prepare_folder(const std::string& dir, const std::string& what, bool create) {
    std::error_code ec;
    const fs::path d = fs::absolute(fs::path(dir), ec).lexically_normal();
    // The folder itself, or the nearest one above it that exists (where it would be created).
    fs::path existing = d;
    while (!fs::exists(existing, ec) && existing.has_relative_path()) existing = existing.parent_path();
    const std::string how = existing == d ? "" : d.string() + " cannot be created: ";
    if (!fs::is_directory(existing, ec)) throw Error(what, how + existing.string() + " is not a folder");
    if (::access(existing.c_str(), W_OK | X_OK) != 0)
        throw Error(what, how + existing.string() + " is not writable (" + std::strerror(errno) + ")");
    if (create && existing != d) {
        fs::create_directories(d, ec);
        if (ec) throw Error(what, d.string() + " cannot be created: " + ec.message());
    }
}

std::string material_hash(const MaterialJob& job, bool source_isotropic) {
    return hash_text(job, source_isotropic, sha256_file(job.input));
}

void check_batch_files(const BatchConfig& config, const std::string& summary_base) {
    // Inputs first: check_distinct_files names the later of two uses, an output.
    std::vector<FileUse> uses;
    if (!config.path.empty()) uses.push_back({config.path, "the configuration", false});
    for (const MaterialJob& m : config.materials) uses.push_back({m.input, "the input of '" + m.name + "'", false});
    for (const MaterialJob& m : config.materials) {
        uses.push_back({m.output, "the output of '" + m.name + "'", true});
        if (!resolve_render_check(m.settings).enabled) continue;
        for (const std::string& l : resolve_render_check(m.settings).lightings)
            for (const char* kind : {"reference", "npf"})
                uses.push_back({render_file(m, l, kind), "a validation render of '" + m.name + "'", true});
    }
    if (!summary_base.empty()) {
        uses.push_back({summary_base + ".json", "the summary", true});
        uses.push_back({summary_base + ".md", "the summary", true});
    }
    check_distinct_files(uses);
}

namespace {

// "[2/7] felt: converted in 1.2 s, 0.007 MB (1/161.9), error 3.1 %, PSNR ...", one line whatever
// the names hold.
std::string progress_line(const std::string& counter, const MaterialResult& r) {
    std::string line = counter + ": " + status_name(r.status);
    if (r.status == MaterialStatus::Failed) {
        line += ": " + r.reason;
    } else {
        line += " in " + fmt("%.2f s", r.seconds);
        if (r.output_bytes) line += ", " + fmt("%.3f MB", double(r.output_bytes) / 1e6);
        if (r.ratio()) line += " (1/" + fmt("%.1f", *r.ratio()) + ")";
        if (r.error_mean) line += ", error " + fmt("%.2f %%", 100.0 * *r.error_mean);
        // "PSNR 47.10 dB, the worst of studio 55.02 (floor 63.10), key-rim 50.21 (floor 64.02), directional 47.10"
        if (r.psnr) {
            const auto db = [](double v) { return std::isfinite(v) ? fmt("%.2f", v) : std::string("inf"); };
            line += ", PSNR " + db(*r.psnr) + " dB";
            std::string each;
            for (const LightingCheck& c : r.lightings) {
                each += (each.empty() ? "" : ", ") + c.lighting + " " + db(c.psnr);
                if (std::isfinite(c.psnr_floor)) each += " (floor " + db(c.psnr_floor) + ")";
            }
            if (r.lightings.size() > 1) line += ", the worst of " + each;
            else if (r.psnr_floor) line += " (noise floor " + db(*r.psnr_floor) + " dB)";
        }
        if (!r.reason.empty()) line += " (" + r.reason + ")";
    }
    return printable(line);
}

}  // namespace

BatchSummary run_batch(const BatchConfig& config, const BatchOptions& options) {
    const auto start = Clock::now();
    const auto log = [&](const std::string& line) {
        if (options.log) options.log(line);
    };
    const auto stopped = [&options] { return options.stop && *options.stop != 0; };
    BatchSummary summary;
    summary.config = config.path;
    summary.shard_index = options.shard.index;
    summary.shard_count = options.shard.count;
    summary.shards = {options.shard.index};
    summary.config_materials = config.materials.size();
    summary.warnings = config.warnings;

    check_batch_files(config, "");
    BatchFolders folders(config.output_dir, options.shard);
    const std::vector<std::size_t> members = shard_members(config.materials.size(), options.shard);
    for (std::size_t index : members) {
        if (resolve_render_check(config.materials[index].settings).enabled) {
            folders.check_renders();
            break;
        }
    }

    MaterialContext here;  // in-process: no worker executable
    here.stage = &folders.stage();
    here.folders = &folders;
    here.force = options.force;
    here.shard = options.shard.index;
    std::size_t done = 0;
    for (std::size_t index : members) {
        if (stopped()) break;
        MaterialJob job = config.materials[index];
        if (options.threads > 0) job.settings["threads"] = {std::to_string(options.threads), "--threads"};
        if (!options.memory_limit.empty()) job.settings["memory_limit"] = {options.memory_limit, "--memory-limit"};
        if (!options.time_limit.empty()) job.settings["time_limit"] = {options.time_limit, "--time-limit"};
        const auto t0 = Clock::now();
        const std::string counter = "[" + std::to_string(++done) + "/" + std::to_string(members.size()) + "] " + job.name;
        std::optional<MaterialResult> r =
            options.worker_executable.empty() ? process_material(job, here) : run_in_worker(job, folders, options);
        folders.stage().clear();
        if (!r) break;  // stopped while its worker ran
        r->seconds = seconds_since(t0);
        log(progress_line(counter, *r));
        summary.materials.push_back(std::move(*r));
    }
    if (stopped()) summary.stopped_by = int(*options.stop);
    summary.seconds = seconds_since(start);
    return summary;
}

namespace {

// The job a worker was given, read without following a link, and the stage folder it names,
// which must be the one the batch made, holding this very job file.
struct WorkerJob {
    YAML::Node node;
    OwnedFolder stage;
};

WorkerJob read_worker_job(const std::string& job_path) {
    const int fd = ::open(job_path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) throw Error(job_path, std::string("cannot open the job: ") + std::strerror(errno));
    std::string text;
    struct stat job {};
    try {
        text = read_text_file(fd, job_path, "an npf batch job", kConfigTextBounds);
        if (::fstat(fd, &job) != 0) throw Error(job_path, std::string("cannot examine the job: ") + std::strerror(errno));
    } catch (...) {
        ::close(fd);
        throw;
    }
    ::close(fd);
    const YAML::Node j = YAML::Load(text);
    if (!j.IsMap() || !j["npf_batch_worker_job"] || j["npf_batch_worker_job"].as<int>() != 2) throw Error(job_path, "not an npf batch job");
    OwnedFolder stage = OwnedFolder::reopen(j["stage"].as<std::string>(), std::stoull(j["stage_device"].as<std::string>()),
                                            std::stoull(j["stage_inode"].as<std::string>()), kOwner);
    struct stat there {};
    if (::fstatat(stage.descriptor(), file_name(job_path).c_str(), &there, AT_SYMLINK_NOFOLLOW) != 0 || there.st_dev != job.st_dev ||
        there.st_ino != job.st_ino)
        throw Error(job_path, "is not a job in the work folder the batch made: not used");
    return WorkerJob{j, std::move(stage)};
}

// RLIMIT_DATA (heap and private writable mappings: what a material's tables take), not
// RLIMIT_AS, which also counts the libraries' code and every thread's 64 MiB malloc arena
// reservation, so that its value would depend on the thread count. Set before any material is
// read; an allocation past it fails (std::bad_alloc in C++ code).
void limit_memory(std::uint64_t bytes, const std::string& job_path) {
    struct rlimit limit {};
    ::getrlimit(RLIMIT_DATA, &limit);
    const rlim_t want = rlim_t(bytes);
    limit.rlim_cur = limit.rlim_max == RLIM_INFINITY ? want : std::min(want, limit.rlim_max);
    if (::setrlimit(RLIMIT_DATA, &limit) != 0) throw Error(job_path, std::string("cannot set the memory limit: ") + std::strerror(errno));
}

}  // namespace

int run_batch_worker(const std::string& job_path) {
    // Dies with the batch (kill -9 included) rather than finishing on its own; the parent's pid
    // in the job catches a parent that died before this line.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    try {
        const WorkerJob w = read_worker_job(job_path);
        const YAML::Node& j = w.node;
        if (long(::getppid()) != j["parent"].as<long>()) {
            std::fprintf(stderr, "npf batch --worker: the batch that started this worker has ended\n");
            return 3;
        }
        MaterialContext ctx;
        ctx.in_worker = true;
        ctx.stage = &w.stage;
        ctx.force = j["force"].as<bool>();
        ctx.shard = j["shard"].as<int>();
        ctx.memory_limit = std::stoull(j["memory_limit"].as<std::string>());
        if (ctx.memory_limit > 0) limit_memory(ctx.memory_limit, job_path);
        MaterialJob job;
        job.name = j["name"].as<std::string>();
        job.input = j["input"].as<std::string>();
        job.output = j["output"].as<std::string>();
        job.origin = j["origin"].as<std::string>();
        for (const auto& kv : j["settings"]) job.settings[kv.first.as<std::string>()] = {kv.second[0].as<std::string>(), kv.second[1].as<std::string>()};
        BatchSummary answer;
        answer.config = job_path;
        answer.materials.push_back(process_material(job, ctx));
        // The list of finished files first: the answer's presence says both are complete.
        YAML::Emitter moves;
        moves << YAML::BeginSeq;
        for (const auto& [name, to] : ctx.moves)
            moves << YAML::Flow << YAML::BeginSeq << YAML::DoubleQuoted << name << YAML::DoubleQuoted << to << YAML::EndSeq;
        moves << YAML::EndSeq;
        w.stage.write_new_file(j["moves"].as<std::string>(), std::string(moves.c_str()) + "\n");
        w.stage.write_new_file(j["result"].as<std::string>(), summary_json(answer));
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "npf batch --worker: %s\n", printable(e.what()).c_str());
        return 3;
    }
}

}  // namespace npf::batch
