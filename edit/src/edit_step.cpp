#include <npf/edit/edit_step.h>

#include "tables.h"

#include <npf/core/number_text.h>
#include <npf/edit/albedo_limit.h>
#include <npf/edit/colour_edits.h>
#include <npf/edit/compression.h>
#include <npf/edit/recipe.h>
#include <npf/shading/npf_texture_file.h>

#include <utility>

namespace npf::edit {

EditStep EditStep::ndf(const Mat3& m, std::string label) {
    EditStep s;
    s.kind = Kind::Ndf;
    s.matrix = m;
    s.label = std::move(label);
    s.operation = [m](const NpfModel& model, const EditOptions& o, EditRecord* rec) { return transform_ndf(model, m, o.ndf, rec); };
    return s;
}

EditStep EditStep::diffuse_from(std::string path, double scale) {
    EditStep s;
    s.kind = Kind::DiffuseMaterial;
    s.label = "diffuse from " + path + (scale != 1.0 ? " x " + number_text(scale) : "");
    s.path = std::move(path);
    s.scale = scale;
    s.operation = [path = s.path, scale](const NpfModel& model, const EditOptions&, EditRecord* rec) {
        return replace_diffuse(model, read_npf_texture(path), scale, rec);
    };
    return s;
}

EditStep EditStep::diffuse_albedo(color::SampledSpectrum albedo, std::string label) {
    EditStep s;
    s.kind = Kind::DiffuseSpectrum;
    s.spectrum = std::move(albedo);
    s.label = std::move(label);
    s.operation = [spectrum = s.spectrum](const NpfModel& model, const EditOptions&, EditRecord* rec) {
        return replace_diffuse_albedo(model, spectrum, rec);
    };
    return s;
}

EditStep EditStep::diffuse_albedo(const color::Rgb& linear, std::string label) {
    EditStep s;
    s.kind = Kind::DiffuseRgb;
    s.rgb = linear;
    s.label = std::move(label);
    s.operation = [linear](const NpfModel& model, const EditOptions&, EditRecord* rec) { return replace_diffuse_albedo(model, linear, rec); };
    return s;
}

EditStep EditStep::specular_from(std::string path, double scale, bool keep_brightness) {
    EditStep s;
    s.kind = Kind::SpecularMaterial;
    s.label = "specular from " + path + (scale != 1.0 ? " x " + number_text(scale) : "") +
              (keep_brightness ? ", brightness kept" : "");
    s.path = std::move(path);
    s.scale = scale;
    s.keep_brightness = keep_brightness;
    s.operation = [path = s.path, swap = SpecularSwap{scale, keep_brightness}](const NpfModel& model, const EditOptions&, EditRecord* rec) {
        return replace_specular(model, read_npf_texture(path), swap, rec);
    };
    return s;
}

EditStep EditStep::thin_film(ThinFilm film, std::string label) {
    EditStep s;
    s.kind = Kind::ThinFilm;
    s.film = std::move(film);
    s.label = std::move(label);
    s.operation = [film = s.film](const NpfModel& model, const EditOptions&, EditRecord* rec) { return apply_thin_film(model, film, rec); };
    return s;
}

EditStep EditStep::compress(const CompressionOptions& options, std::string label) {
    EditStep s;
    s.kind = Kind::Compress;
    s.compression = options;
    s.label = std::move(label);
    s.operation = [options](const NpfModel& model, const EditOptions&, EditRecord* rec) { return compress_model(model, options, rec); };
    return s;
}

EditStep EditStep::limit_albedo(double cap) {
    EditStep s;
    s.kind = Kind::LimitAlbedo;
    s.cap = cap;
    s.label = "limit the directional albedo to " + number_text(cap);
    s.operation = [cap](const NpfModel& model, const EditOptions& o, EditRecord* rec) {
        AlbedoLimit limit;
        limit.cap = cap;
        limit.threads = o.albedo.threads;
        limit.progress = o.progress;
        return npf::edit::limit_albedo(model, limit, rec);
    };
    return s;
}

}  // namespace npf::edit
