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

namespace {

// A step of `kind` that runs `operation`; the factories add the kind's fields.
EditStep step_of(EditStep::Kind kind, std::string label, decltype(EditStep::operation) operation) {
    EditStep s;
    s.kind = kind;
    s.label = std::move(label);
    s.operation = std::move(operation);
    return s;
}

}  // namespace

EditStep EditStep::ndf(const Mat3& m, std::string label) {
    EditStep s = step_of(Kind::Ndf, std::move(label), [m](const NpfModel& model, const EditOptions& o, EditRecord* rec) {
        return transform_ndf(model, m, o.ndf, rec);
    });
    s.matrix = m;
    return s;
}

EditStep EditStep::diffuse_from(std::string path, double scale) {
    std::string label = "diffuse from " + path + (scale != 1.0 ? " x " + number_text(scale) : "");
    EditStep s = step_of(Kind::DiffuseMaterial, std::move(label), [path, scale](const NpfModel& model, const EditOptions&, EditRecord* rec) {
        return replace_diffuse(model, read_npf_texture(path), scale, rec);
    });
    s.path = std::move(path);
    s.scale = scale;
    return s;
}

EditStep EditStep::diffuse_albedo(color::SampledSpectrum albedo, std::string label) {
    EditStep s = step_of(Kind::DiffuseSpectrum, std::move(label), [albedo](const NpfModel& model, const EditOptions&, EditRecord* rec) {
        return replace_diffuse_albedo(model, albedo, rec);
    });
    s.spectrum = std::move(albedo);
    return s;
}

EditStep EditStep::diffuse_albedo(const color::Rgb& linear, std::string label) {
    EditStep s = step_of(Kind::DiffuseRgb, std::move(label), [linear](const NpfModel& model, const EditOptions&, EditRecord* rec) {
        return replace_diffuse_albedo(model, linear, rec);
    });
    s.rgb = linear;
    return s;
}

EditStep EditStep::specular_from(std::string path, double scale, bool keep_brightness) {
    std::string label = "specular from " + path + (scale != 1.0 ? " x " + number_text(scale) : "") +
                        (keep_brightness ? ", brightness kept" : "");
    const SpecularSwap swap{scale, keep_brightness};
    EditStep s = step_of(Kind::SpecularMaterial, std::move(label), [path, swap](const NpfModel& model, const EditOptions&, EditRecord* rec) {
        return replace_specular(model, read_npf_texture(path), swap, rec);
    });
    s.path = std::move(path);
    s.scale = scale;
    s.keep_brightness = keep_brightness;
    return s;
}

EditStep EditStep::thin_film(ThinFilm film, std::string label) {
    EditStep s = step_of(Kind::ThinFilm, std::move(label), [film](const NpfModel& model, const EditOptions&, EditRecord* rec) {
        return apply_thin_film(model, film, rec);
    });
    s.film = std::move(film);
    return s;
}

EditStep EditStep::compress(const CompressionOptions& options, std::string label) {
    EditStep s = step_of(Kind::Compress, std::move(label), [options](const NpfModel& model, const EditOptions&, EditRecord* rec) {
        return compress_model(model, options, rec);
    });
    s.compression = options;
    return s;
}

EditStep EditStep::limit_albedo(double cap) {
    EditStep s = step_of(Kind::LimitAlbedo, "limit the directional albedo to " + number_text(cap),
                         [cap](const NpfModel& model, const EditOptions& o, EditRecord* rec) {
                             AlbedoLimit limit;
                             limit.cap = cap;
                             limit.threads = o.albedo.threads;
                             limit.progress = o.progress;
                             return npf::edit::limit_albedo(model, limit, rec);
                         });
    s.cap = cap;
    return s;
}

}  // namespace npf::edit
