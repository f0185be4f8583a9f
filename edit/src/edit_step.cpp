#include <npf/edit/edit_step.h>

#include "tables.h"

#include <npf/core/number_text.h>

#include <utility>

namespace npf::edit {

EditStep EditStep::ndf(const Mat3& m, std::string label) {
    EditStep s;
    s.kind = Kind::Ndf;
    s.matrix = m;
    s.label = std::move(label);
    return s;
}

EditStep EditStep::diffuse_from(std::string path, double scale) {
    EditStep s;
    s.kind = Kind::DiffuseMaterial;
    s.label = "diffuse from " + path + (scale != 1.0 ? " x " + number_text(scale) : "");
    s.path = std::move(path);
    s.scale = scale;
    return s;
}

EditStep EditStep::diffuse_albedo(color::SampledSpectrum albedo, std::string label) {
    EditStep s;
    s.kind = Kind::DiffuseSpectrum;
    s.spectrum = std::move(albedo);
    s.label = std::move(label);
    return s;
}

EditStep EditStep::diffuse_albedo(const color::Rgb& linear, std::string label) {
    EditStep s;
    s.kind = Kind::DiffuseRgb;
    s.rgb = linear;
    s.label = std::move(label);
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
    return s;
}

EditStep EditStep::thin_film(ThinFilm film, std::string label) {
    EditStep s;
    s.kind = Kind::ThinFilm;
    s.film = std::move(film);
    s.label = std::move(label);
    return s;
}

EditStep EditStep::compress(const CompressionOptions& options, std::string label) {
    EditStep s;
    s.kind = Kind::Compress;
    s.compression = options;
    s.label = std::move(label);
    return s;
}

EditStep EditStep::limit_albedo(double cap) {
    EditStep s;
    s.kind = Kind::LimitAlbedo;
    s.cap = cap;
    s.label = "limit the directional albedo to " + number_text(cap);
    return s;
}

}  // namespace npf::edit
