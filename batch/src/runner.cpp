#include <npf/batch/runner.h>

#include "worker_process.h"

#include <npf/batch/content_hash.h>
#include <npf/core/atomic_file.h>
#include <npf/converter/convert.h>
#include <npf/converter/convert_settings_table.h>
#include <npf/converter/open_material.h>
#include <npf/core/error.h>
#include <npf/core/version.h>
#include <npf/core/text.h>
#include <npf/edit/recipe.h>
#include <npf/render/default_environment.h>
#include <npf/render/environment_map.h>
#include <npf/render/image_metrics.h>
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
#include <map>
#include <memory>
#include <optional>

#include <ctime>
#include <csignal>
#include <fstream>
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
    const fs::path dir = fs::path(recipe).parent_path();
    std::vector<YAML::Node> todo;
    try {
        todo.push_back(YAML::LoadFile(recipe));
    } catch (const YAML::Exception&) {
        return t;  // the recipe's own loader reports the problem
    }
    std::map<std::string, std::string> files;
    while (!todo.empty()) {
        const YAML::Node n = todo.back();
        todo.pop_back();
        if (n.IsScalar()) {
            const std::string v = n.Scalar();
            if (v.empty() || v.size() > 4096 || v.find('\0') != std::string::npos) continue;
            const fs::path p = fs::path(v).is_absolute() ? fs::path(v) : dir / v;
            std::error_code ec;
            if (fs::is_regular_file(p, ec)) files[v] = sha256_file(p.string());
        } else if (n.IsSequence()) {
            for (const YAML::Node& c : n) todo.push_back(c);
        } else if (n.IsMap()) {
            for (const auto& kv : n) todo.push_back(kv.second);
        }
    }
    for (const auto& [name, h] : files) t += "edit-file " + name + " " + h + "\n";
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
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
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
    r.error_mean = attr_number(h, m + "error_rel_rms_mean");
    r.error_max = attr_number(h, m + "error_rel_rms_max");
    r.fitted_error_mean = attr_number(h, m + "error_fitted_rel_rms_mean");
    r.fitted_error_max = attr_number(h, m + "error_fitted_rel_rms_max");
    r.albedo_max = attr_number(h, m + "albedo_max");
    r.edits.clear();
    for (int k = 1; k < 1000; ++k) {
        char key[32];
        std::snprintf(key, sizeof key, "edit_%03d", k);
        const auto it = h.find(m + key);
        if (it == h.end()) break;
        r.edits.push_back(first_line(it->second));
    }
}

void fill_from_render_header(MaterialResult& r, const std::map<std::string, std::string>& h) {
    r.psnr = attr_number(h, "npf:batch_psnr");
    r.psnr_floor = attr_number(h, "npf:batch_psnr_floor");
    r.ssim = attr_number(h, "npf:batch_ssim");
    r.relmse = attr_number(h, "npf:batch_relmse");
}

// Holds an exclusive lock on a file for the lifetime of the object (released by the kernel if
// the process dies).
class FileLock {
public:
    explicit FileLock(const std::string& path) {
        m_fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (m_fd < 0) throw Error(path, std::string("cannot create the lock file: ") + std::strerror(errno));
        if (::flock(m_fd, LOCK_EX | LOCK_NB) != 0) {
            ::close(m_fd);
            throw Error(path, "another npf batch is running this shard (the lock is held)");
        }
    }
    ~FileLock() { ::close(m_fd); }
    FileLock(const FileLock&) = delete;
    FileLock& operator=(const FileLock&) = delete;

private:
    int m_fd = -1;
};

void clear_folder(const std::string& dir) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) fs::remove_all(e.path(), ec);
}

// A finished file from the staging folder to its place, by the rules every npf output follows
// (atomic_file.h): a link at the output's name is followed, a FIFO written through, a folder
// refused, the bytes synced before the name changes.
void move_into_place(const std::string& from, const std::string& to) {
    std::error_code ec;
    fs::create_directories(fs::path(to).parent_path(), ec);
    publish_staged_file(from, to);
}

std::string shard_tag(const Shard& s) { return "shard-" + std::to_string(s.index) + "-of-" + std::to_string(s.count); }

std::string render_file(const MaterialJob& job, const char* kind) {
    const fs::path out(job.output);
    return (out.parent_path() / "renders" / (out.stem().string() + "." + kind + ".exr")).string();
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

std::string render_hash_of(const std::string& material_hash, const RenderCheck& check) {
    const std::string env = check.env.empty() ? render::default_environment_map_path() : check.env;
    return sha256_hex(material_hash + "\nrender size=" + std::to_string(check.size) + " spp=" + std::to_string(check.spp) +
                      " seed=" + std::to_string(check.seed) + " sampling=env floor=paired\nenv " + sha256_file(env) + "\n");
}

// How a material is processed: in this process, or in a worker whose finished files the parent
// moves into place (so that a worker killed at any point publishes nothing).
struct MaterialContext {
    std::string stage;
    bool force = false;
    int shard = 0;
    bool in_worker = false;
    std::uint64_t memory_limit = 0;  // the worker's, for messages
    std::map<std::string, render::EnvironmentMap> environments;
    std::vector<std::pair<std::string, std::string>> moves;  // worker: (staged, final), in order

    // Where the finished file is to be read from afterwards.
    std::string publish(const std::string& from, const std::string& to) {
        if (in_worker) {
            moves.emplace_back(from, to);
            return from;
        }
        move_into_place(from, to);
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

// One material: checked against its output's hash, converted, edited, stamped, written, and
// rendered when asked; every problem becomes its failed status and reason.
MaterialResult process_material(const MaterialJob& job, MaterialContext& ctx) {
    std::error_code ec;
    MaterialResult r = result_for(job, ctx.shard);
    const std::string fit_path = (fs::path(ctx.stage) / (job.name + ".fit.exr")).string();
    const std::string final_stage = (fs::path(ctx.stage) / (job.name + ".exr")).string();
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
        std::optional<std::map<std::string, std::string>> render_header;
        if (check.enabled) {
            render_hash = render_hash_of(r.hash, check);
            render_header = header_of(render_file(job, "npf"), false);
        }
        const bool render_up_to_date = !check.enabled || (up_to_date && render_header && render_header->count("npf:batch_hash") &&
                                                          render_header->at("npf:batch_hash") == render_hash &&
                                                          fs::is_regular_file(render_file(job, "reference"), ec));

        std::string output = job.output;  // where the output is read from below
        if (!up_to_date) {
            ConvertSettings s = resolve_convert_settings(job.settings, isotropic);
            const ConvertReport rep = convert_material(*source, fit_path, s);
            NpfModel model = read_npf_texture(fit_path);
            fs::remove(fit_path, ec);
            const auto e = job.settings.find("edit");
            if (e != job.settings.end() && !e->second.value.empty()) {
                const edit::EditRecipe recipe = edit::load_edit_recipe(e->second.value);
                edit::EditResult edited = edit::apply_edits(model, recipe.steps, recipe.options);
                model = std::move(edited.model);
            }
            model.metadata.emplace_back(npf_exr::kMetaBatchName, job.name);
            model.metadata.emplace_back(npf_exr::kMetaBatchSettings, canonical_settings(job.settings));
            model.metadata.emplace_back(npf_exr::kMetaBatchHash, r.hash);
            write_npf_texture(model, final_stage);  // no time stamp: the bytes are the content's
            output = ctx.publish(final_stage, job.output);
            if (rep.fit.invalid_values > 0) r.reason = std::to_string(rep.fit.invalid_values) + " invalid source values ignored";
            r.status = MaterialStatus::Converted;
        } else {
            r.status = MaterialStatus::Skipped;
        }
        r.output_bytes = file_size(output);
        if (const auto h = header_of(output, true)) fill_from_header(r, *h);

        if (check.enabled && !render_up_to_date) {
            const std::string env_path = check.env.empty() ? render::default_environment_map_path() : check.env;
            auto it = ctx.environments.find(env_path);
            if (it == ctx.environments.end()) it = ctx.environments.emplace(env_path, render::EnvironmentMap::load(env_path)).first;
            // Paired (docs/metrics.md sec. 5): environment sampling only at one seed, so both
            // images are estimated at the same light directions; the pair again at the next
            // seed gives the PSNR's noise floor.
            render::RenderOptions ro;
            ro.width = ro.height = check.size;
            ro.spp = check.spp;
            ro.seed = check.seed;
            ro.threads = check.threads;
            ro.sampling = render::Sampling::Environment;
            const std::unique_ptr<Brdf> fitted = open_material(output);
            const render::RenderResult reference = render::render(*source, it->second, ro);
            const render::RenderResult test = render::render(*fitted, it->second, ro);
            render::RenderOptions ro2 = ro;
            ro2.seed = check.seed + 1;
            const render::RenderResult reference2 = render::render(*source, it->second, ro2);
            const render::RenderResult test2 = render::render(*fitted, it->second, ro2);
            const render::ImageMetrics metrics = render::compare_images(reference.image, test.image, {}, "reference", "npf");
            const render::NoiseFloor floor =
                render::paired_noise_floor(reference.image, test.image, reference2.image, test2.image, {}, "reference", "npf");
            r.psnr = metrics.psnr, r.ssim = metrics.ssim, r.relmse = metrics.relmse;
            r.psnr_floor = floor.psnr;
            render::RenderMetadata ref_meta = render::describe_render(reference, ro, it->second);
            ref_meta.insert(ref_meta.begin(), {"npf:material", job.input});
            ref_meta.emplace_back("npf:batch_hash", render_hash);
            render::RenderMetadata npf_meta = render::describe_render(test, ro, it->second);
            npf_meta.insert(npf_meta.begin(), {"npf:material", job.output});
            npf_meta.emplace_back("npf:batch_hash", render_hash);
            npf_meta.emplace_back("npf:batch_psnr", fmt("%.9g", metrics.psnr));
            npf_meta.emplace_back("npf:batch_psnr_floor", fmt("%.9g", floor.psnr));
            npf_meta.emplace_back("npf:batch_ssim", fmt("%.9g", metrics.ssim));
            npf_meta.emplace_back("npf:batch_relmse", fmt("%.9g", metrics.relmse));
            const std::string ref_stage = (fs::path(ctx.stage) / (job.name + ".reference.exr")).string();
            const std::string npf_stage = (fs::path(ctx.stage) / (job.name + ".npf.exr")).string();
            render::write_render_exr(ref_stage, reference, ref_meta);
            render::write_render_exr(npf_stage, test, npf_meta);
            ctx.publish(ref_stage, render_file(job, "reference"));
            ctx.publish(npf_stage, render_file(job, "npf"));  // last: its hash says both are done
            if (r.status == MaterialStatus::Skipped) r.reason = "validation render redone";
        } else if (check.enabled && render_header) {
            fill_from_render_header(r, *render_header);
        }
    } catch (const std::bad_alloc&) {
        r.status = MaterialStatus::Failed;
        r.reason = job.input + ": ran out of memory (" + memory_note(ctx.memory_limit) + ")";
    } catch (const Error& e) {
        r.status = MaterialStatus::Failed;
        r.reason = e.what();
    } catch (const std::exception& e) {
        r.status = MaterialStatus::Failed;
        r.reason = job.input + ": internal error: " + e.what();
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
            const auto render_header = header_of(render_file(job, "npf"), false);
            if (!render_header || !render_header->count("npf:batch_hash") ||
                render_header->at("npf:batch_hash") != render_hash_of(stored, check) ||
                !fs::is_regular_file(render_file(job, "reference"), ec))
                return std::nullopt;
            fill_from_render_header(r, *render_header);
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

// The job file a worker reads (YAML): the material, the stage folder and where its answers go.
void write_job(const std::string& path, const MaterialJob& job, const MaterialContext& ctx, const std::string& result,
               const std::string& moves) {
    YAML::Emitter out;
    // Quoted, so that no text reads back as null, a number or a boolean.
    const auto q = [&out](const std::string& text) { out << YAML::DoubleQuoted << text; };
    out << YAML::BeginMap;
    out << YAML::Key << "npf_batch_worker_job" << YAML::Value << 1;
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
    q(ctx.stage);
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
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f << out.c_str() << "\n";
    f.close();
    if (!f) throw Error(path, "cannot write the worker's job file");
}

void write_text_file(const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f << text;
    f.close();
    if (!f) throw Error(path, "cannot write");
}

// Runs one material in a worker process under its limits and turns however it ended into a
// result: the worker's own, or a failure naming the input and why (signal, limit, exit status).
MaterialResult run_in_worker(const MaterialJob& job, const std::string& executable, const std::string& stage, bool force, int shard) {
    MaterialResult failed = result_for(job, shard);
    failed.status = MaterialStatus::Failed;
    MaterialLimits limits;
    try {
        limits = resolve_limits(job.settings);
    } catch (const Error& e) {
        failed.reason = e.what();
        return failed;
    }
    if (!force) {
        if (std::optional<MaterialResult> skipped = up_to_date_result(job, shard)) return *skipped;
    }
    MaterialContext ctx;
    ctx.stage = stage;
    ctx.force = force;
    ctx.shard = shard;
    ctx.memory_limit = limits.memory_bytes;
    const fs::path base = fs::path(stage) / job.name;
    const std::string job_file = base.string() + ".job.yaml", result = base.string() + ".result.json",
                      moves = base.string() + ".moves.yaml", log = base.string() + ".worker.log";
    try {
        write_job(job_file, job, ctx, result, moves);
    } catch (const Error& e) {
        failed.reason = e.what();
        return failed;
    }
    const detail::WorkerEnd end = detail::run_worker_process(executable, {"batch", "--worker", job_file}, log, limits.seconds);
    const std::string tail = detail::last_line(log);
    const std::string said = tail.empty() ? "" : " (its last words: " + tail + ")";
    if (!end.start_error.empty()) {
        failed.reason = "cannot start the worker process " + executable + ": " + end.start_error;
        return failed;
    }
    if (end.timed_out) {
        failed.reason = job.input + ": took longer than " + describe_seconds(limits.seconds) + " (time_limit), stopped";
        return failed;
    }
    if (end.signal > 0) {
        if (tail.find("bad_alloc") != std::string::npos) {
            failed.reason = job.input + ": ran out of memory (" + memory_note(limits.memory_bytes) + "), " + detail::signal_text(end.signal);
        } else {
            failed.reason = job.input + ": killed by " + detail::signal_text(end.signal);
            if (end.signal == SIGKILL)
                failed.reason += " from outside, at " + describe_memory(std::uint64_t(end.peak_resident_bytes)) +
                                 " resident (the system's out-of-memory killer?)";
            failed.reason += said;
        }
        return failed;
    }
    if (end.exited && end.exit_code != 0) {
        failed.reason = job.input + ": the worker process exited with status " + std::to_string(end.exit_code) + said;
        return failed;
    }
    // Ended normally (or its status was lost): its answer, and the files it finished.
    BatchSummary answer;
    std::vector<std::pair<std::string, std::string>> to_move;
    try {
        answer = read_summary_json(result);
        const YAML::Node list = YAML::LoadFile(moves);
        for (const YAML::Node& m : list) to_move.emplace_back(m[0].as<std::string>(), m[1].as<std::string>());
    } catch (const std::exception& e) {
        failed.reason = job.input + ": the worker process ended without an answer (" + std::string(e.what()) + ")" + said;
        return failed;
    }
    if (answer.materials.size() != 1 || answer.materials[0].name != job.name) {
        failed.reason = job.input + ": the worker process answered for another material";
        return failed;
    }
    MaterialResult r = answer.materials[0];
    try {
        for (const auto& [from, to] : to_move) move_into_place(from, to);
    } catch (const Error& e) {
        r.status = MaterialStatus::Failed;
        r.reason = e.what();
    }
    return r;
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

BatchSummary run_batch(const BatchConfig& config, const BatchOptions& options) {
    const auto start = Clock::now();
    const auto log = [&](const std::string& line) {
        if (options.log) options.log(line);
    };
    BatchSummary summary;
    summary.config = config.path;
    summary.shard_index = options.shard.index;
    summary.shard_count = options.shard.count;
    summary.shards = {options.shard.index};
    summary.config_materials = config.materials.size();
    summary.warnings = config.warnings;

    std::error_code ec;
    fs::create_directories(config.output_dir, ec);
    if (ec) throw Error(config.output_dir, "cannot create the output folder: " + ec.message());
    const std::string work = (fs::path(config.output_dir) / ".npf-batch").string();
    const std::string stage = (fs::path(work) / shard_tag(options.shard)).string();
    fs::create_directories(stage, ec);
    if (ec) throw Error(stage, "cannot create the work folder: " + ec.message());
    const FileLock lock(stage + ".lock");
    clear_folder(stage);  // what a killed run left

    MaterialContext here;  // in-process: no worker executable
    here.stage = stage;
    here.force = options.force;
    here.shard = options.shard.index;
    const std::vector<std::size_t> members = shard_members(config.materials.size(), options.shard);
    std::size_t done = 0;
    for (std::size_t index : members) {
        MaterialJob job = config.materials[index];
        if (options.threads > 0) job.settings["threads"] = {std::to_string(options.threads), "--threads"};
        if (!options.memory_limit.empty()) job.settings["memory_limit"] = {options.memory_limit, "--memory-limit"};
        if (!options.time_limit.empty()) job.settings["time_limit"] = {options.time_limit, "--time-limit"};
        const auto t0 = Clock::now();
        const std::string counter = "[" + std::to_string(++done) + "/" + std::to_string(members.size()) + "] " + job.name;
        MaterialResult r = options.worker_executable.empty()
                               ? process_material(job, here)
                               : run_in_worker(job, options.worker_executable, stage, options.force, options.shard.index);
        clear_folder(stage);
        r.seconds = seconds_since(t0);
        std::string line = counter + ": " + status_name(r.status);
        if (r.status == MaterialStatus::Failed) {
            line += ": " + r.reason;
        } else {
            line += " in " + fmt("%.2f s", r.seconds);
            if (r.output_bytes) line += ", " + fmt("%.3f MB", double(r.output_bytes) / 1e6);
            if (r.ratio()) line += " (1/" + fmt("%.1f", *r.ratio()) + ")";
            if (r.error_mean) line += ", error " + fmt("%.2f %%", 100.0 * *r.error_mean);
            if (r.psnr) {
                line += ", PSNR " + fmt("%.2f dB", *r.psnr);
                if (r.psnr_floor) line += " (noise floor " + fmt("%.2f dB", *r.psnr_floor) + ")";
            }
            if (!r.reason.empty()) line += " (" + r.reason + ")";
        }
        log(line);
        summary.materials.push_back(std::move(r));
    }
    summary.seconds = seconds_since(start);
    return summary;
}

int run_batch_worker(const std::string& job_path) {
    // Dies with the batch (kill -9 included) rather than finishing on its own; the parent's pid
    // in the job catches a parent that died before this line.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    try {
        const YAML::Node j = YAML::LoadFile(job_path);
        if (!j["npf_batch_worker_job"] || j["npf_batch_worker_job"].as<int>() != 1) throw Error(job_path, "not an npf batch job");
        if (long(::getppid()) != j["parent"].as<long>()) {
            std::fprintf(stderr, "npf batch --worker: the batch that started this worker has ended\n");
            return 3;
        }
        MaterialContext ctx;
        ctx.in_worker = true;
        ctx.stage = j["stage"].as<std::string>();
        ctx.force = j["force"].as<bool>();
        ctx.shard = j["shard"].as<int>();
        ctx.memory_limit = std::stoull(j["memory_limit"].as<std::string>());
        if (ctx.memory_limit > 0) {
            // RLIMIT_DATA (heap and private writable mappings: what a material's tables take), not
            // RLIMIT_AS, which also counts the libraries' code and every thread's 64 MiB malloc
            // arena reservation, so that its value would depend on the thread count. Set before
            // anything is read; an allocation past it fails (std::bad_alloc in C++ code).
            struct rlimit limit {};
            ::getrlimit(RLIMIT_DATA, &limit);
            const rlim_t want = rlim_t(ctx.memory_limit);
            limit.rlim_cur = limit.rlim_max == RLIM_INFINITY ? want : std::min(want, limit.rlim_max);
            if (::setrlimit(RLIMIT_DATA, &limit) != 0) throw Error(job_path, std::string("cannot set the memory limit: ") + std::strerror(errno));
        }
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
        for (const auto& [from, to] : ctx.moves)
            moves << YAML::Flow << YAML::BeginSeq << YAML::DoubleQuoted << from << YAML::DoubleQuoted << to << YAML::EndSeq;
        moves << YAML::EndSeq;
        write_text_file(j["moves"].as<std::string>(), std::string(moves.c_str()) + "\n");
        write_text_file(j["result"].as<std::string>(), summary_json(answer));
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "npf batch --worker: %s\n", e.what());
        return 3;
    }
}

}  // namespace npf::batch
