// One edit step: what apply_edits (recipe.h) runs, as the edit kinds (edit_kinds.h) build it from
// a recipe's step or a flag of `npf edit`.
#pragma once

#include <npf/color/spectrum.h>
#include <npf/fit/spectral_compression.h>
#include <npf/edit/ndf_transform.h>
#include <npf/edit/thin_film.h>

#include <functional>
#include <string>

namespace npf::edit {

struct EditOptions;  // recipe.h
struct EditRecord;   // edit_record.h

struct EditStep {
    enum class Kind {
        Ndf,              // matrix (any of the NDF forms)
        DiffuseMaterial,  // rho_d of the NPF file `path`, times scale
        DiffuseSpectrum,  // albedo spectrum
        DiffuseRgb,       // linear sRGB albedo
        SpecularMaterial, // rho_s F of the NPF file `path`, times scale
        ThinFilm,
        Compress,         // D and G re-compressed (compression.h)
        LimitAlbedo,      // G lowered where the directional albedo exceeds `cap` (albedo_limit.h)
    };
    Kind kind = Kind::Ndf;
    std::string label;   // what the user asked, for the history ("stretch tangent 2, bitangent 1")
    std::string origin;  // where it was asked ("recipe.yaml:7", "--rotate"), for errors
    Mat3 matrix;
    std::string path;
    double scale = 1.0;
    bool keep_brightness = false;  // SpecularMaterial
    color::SampledSpectrum spectrum;
    color::Rgb rgb{0, 0, 0};
    ThinFilm film;
    CompressionOptions compression;
    double cap = 1.0;  // LimitAlbedo
    // What the step does to a model, set by the factory that built it: apply_edits runs it, so a
    // new kind brings its own operation (its parameters captured here) and needs no field above
    // and no case in apply_edits. The fields above describe the shipped kinds' parameters.
    std::function<NpfModel(const NpfModel& model, const EditOptions& options, EditRecord* record)> operation;

    static EditStep ndf(const Mat3& m, std::string label);
    static EditStep diffuse_from(std::string path, double scale = 1.0);
    static EditStep diffuse_albedo(color::SampledSpectrum albedo, std::string label);
    static EditStep diffuse_albedo(const color::Rgb& linear, std::string label);
    static EditStep specular_from(std::string path, double scale = 1.0, bool keep_brightness = false);
    static EditStep thin_film(ThinFilm film, std::string label);
    static EditStep compress(const CompressionOptions& options, std::string label);
    static EditStep limit_albedo(double cap);
};

}  // namespace npf::edit
