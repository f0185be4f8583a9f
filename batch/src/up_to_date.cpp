// The parent's check before it starts a worker. The input is not opened as a material (a reader
// that crashes must crash in a worker), so its isotropy is unknown: the output is up to date when
// its hash is the one for either isotropy, which for the same input bytes and npf version only
// the real one can have produced.
#include "material_context.h"

#include "material_hash.h"
#include "output_header.h"
#include "validation_renders.h"

#include <npf/batch/content_hash.h>
#include <npf/shading/npf_texture_layout.h>

#include <cstring>
#include <filesystem>

namespace npf::batch::detail {

namespace fs = std::filesystem;

namespace {

bool ends_with(const std::string& s, const char* tail) {
    const std::size_t n = std::strlen(tail);
    return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

}  // namespace

std::optional<MaterialResult> up_to_date_result(const MaterialJob& job, int shard) {
    try {
        std::error_code ec;
        if (!fs::is_regular_file(job.input, ec)) return std::nullopt;
        const auto header = header_of(job.output, true);
        const std::string key = std::string(npf_exr::kMetadataPrefix) + npf_exr::kMetaBatchHash;
        if (!header || !header->count(key)) return std::nullopt;
        const std::string input_sha = sha256_file(job.input);
        const std::string& stored = header->at(key);
        if (stored != material_hash_of(job, true, input_sha) && stored != material_hash_of(job, false, input_sha)) return std::nullopt;
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
        // Made by an earlier run: its figures are the ones its header records.
        fill_recorded_figures(r, *header);
        return r;
    } catch (const std::exception&) {
        return std::nullopt;  // the worker reports it
    }
}

}  // namespace npf::batch::detail
