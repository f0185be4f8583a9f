// Reading a YAML file whose errors name the file, the line and the key:
//   "recipe.yaml:7: key 'alpha': expected a number".
// One implementation for the analytic recipes, the edit recipes and the batch configurations.
// Needs yaml-cpp (which every user of it already parses with).
#pragma once

#include <npf/color/spectrum.h>
#include <npf/core/error.h>

#include <yaml-cpp/yaml.h>

#include <string>
#include <utility>
#include <vector>

namespace npf {

struct YamlContext {
    std::string source;    // the file's name as errors show it
    std::string base_dir;  // relative paths are taken from here (empty: as given)
    // Unknown keys are reported as 'parent.key' rather than 'key' (batch files nest settings).
    bool qualify_unknown_keys = false;

    // The document `yaml`, which must be a mapping: a syntax error throws npf::Error
    // ("source:LINE", "not valid YAML: ..."), another document Error(source, not_a_mapping).
    YAML::Node load_mapping(const std::string& yaml, const std::string& not_a_mapping) const;

    // "source:LINE" where the node has a position, else "source".
    std::string where(const YAML::Node& node) const;
    [[noreturn]] void fail(const YAML::Node& node, const std::string& key, const std::string& problem) const;

    double number(const YAML::Node& node, const std::string& key) const;  // finite
    double positive(const YAML::Node& node, const std::string& key) const;
    int whole(const YAML::Node& node, const std::string& key, int lo, int hi) const;
    std::string text(const YAML::Node& node, const std::string& key) const;  // any scalar
    // A non-empty path, relative ones from base_dir.
    std::string path(const YAML::Node& node, const std::string& key) const;

    // A spectrum, in any of the spellings material and edit recipes accept alike: a number (a
    // constant), a .spd file (a text ending in .spd or holding a '/'; relative to base_dir),
    // rows [[wavelength_nm, value], ...], or a mapping with one of srgb: [r, g, b],
    // linear_srgb: [r, g, b], spectrum: rows, file: path.
    color::SampledSpectrum spectrum(const YAML::Node& node, const std::string& key) const;
    // Rows [[wavelength_nm, value], ...]: each row two numbers, wavelengths strictly ascending.
    // `rows` must be a sequence.
    color::SampledSpectrum spectrum_rows(const YAML::Node& rows, const std::string& key) const;

    // Every key of `map` must be one of `allowed`, each once, and hold a value unless listed in
    // `may_be_empty`. YAML parsers keep one of two equal keys silently; a file should not.
    void only(const YAML::Node& map, const std::string& key, const std::vector<std::string>& allowed,
              const std::vector<std::string>& may_be_empty = {}) const;

    // Runs make(); an npf::Error it throws (a spectrum file that cannot be read, a value out of
    // range) is reported at this node and key instead, with problem_of's message.
    template <typename Make>
    auto at(const YAML::Node& node, const std::string& key, Make make) const -> decltype(make()) {
        try {
            return make();
        } catch (const Error& e) {
            fail(node, key, problem_of(e));
        }
    }
    // The message an error thrown inside at() gives: by default all of it, "source: problem".
    virtual std::string problem_of(const Error& e) const { return e.what(); }

    virtual ~YamlContext() = default;
};

// The files a YAML document names (a recipe's spectra, an edit's source materials): every scalar
// that is the name of an existing regular file, relative names taken from the document's folder,
// as (name in the document, resolved path), sorted by name. For checks that concern every input of a
// command (outputs must not replace one; a batch redoes an edit when one changes). Nothing for a
// document that does not parse (its own loader reports that) or is above the recipe cap.
std::vector<std::pair<std::string, std::string>> files_named_in_yaml(const std::string& path);

}  // namespace npf
