// Batch configuration: reading and checking a configuration file into its materials (their
// settings: settings.cpp; the batch's own files: own_files.cpp).
#include <npf/batch/config.h>

#include "config_reader.h"
#include "own_files.h"
#include "setting_values.h"

#include <npf/core/error.h>
#include <npf/core/text_input.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>

#include <glob.h>
#include <sys/stat.h>

namespace npf::batch {

namespace fs = std::filesystem;

namespace {

using detail::ConfigReader;
using detail::OwnFiles;

bool has_wildcard(const std::string& p) { return p.find_first_of("*?[") != std::string::npos; }

// Every name a glob matches, sorted (files, folders, links, FIFOs alike).
std::vector<std::string> expand_glob(const std::string& pattern) {
    glob_t g{};
    std::vector<std::string> out;
    if (::glob(pattern.c_str(), 0, nullptr, &g) == 0) {
        for (std::size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
    }
    ::globfree(&g);
    std::sort(out.begin(), out.end());
    return out;
}

// Why a glob's match is not a material file ("a FIFO", "a symbolic link to x, which does not
// exist"); "" for a regular file (links followed), and for a folder, which a glob such as `lib/*`
// matches as a matter of course.
std::string not_a_material_file(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) {
        if (S_ISREG(st.st_mode) || S_ISDIR(st.st_mode)) return "";
        if (S_ISFIFO(st.st_mode)) return "a FIFO (named pipe)";
        if (S_ISSOCK(st.st_mode)) return "a socket";
        if (S_ISCHR(st.st_mode)) return "a character device";
        if (S_ISBLK(st.st_mode)) return "a block device";
        return "not a regular file";
    }
    const int e = errno;
    if (::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
        std::error_code ec;
        const fs::path to = fs::read_symlink(path, ec);
        if (e == ENOENT) return "a symbolic link to " + (ec ? std::string("?") : to.string()) + ", which does not exist";
        return "a symbolic link that cannot be followed (" + std::string(std::strerror(e)) + ")";
    }
    return std::string("a name that cannot be examined (") + std::strerror(e) + ")";
}

std::string stem_of(const std::string& path) { return fs::path(path).stem().string(); }

// The material files a glob matches. The batch's own files are left out first (`excluded`; a
// FIFO at an output's name is one of them), then what is not a material file, said in a warning
// naming it, never silently; `where` ("config.yaml:3") begins the warnings.
std::vector<std::string> glob_materials(const std::string& pattern, const std::string& where, const OwnFiles& own, BatchConfig& c) {
    std::vector<std::string> matches;
    std::size_t own_matched = 0, special = 0;
    for (const std::string& m : expand_glob(pattern)) {
        std::error_code ec;
        if (fs::is_directory(m, ec)) continue;
        if (!own.kind(m).empty()) {
            ++own_matched;
            if (std::find(c.excluded.begin(), c.excluded.end(), m) == c.excluded.end()) c.excluded.push_back(m);
        } else if (const std::string why = not_a_material_file(m); !why.empty()) {
            ++special;
            c.warnings.push_back(where + ": '" + pattern + "' matches " + m + ", " + why + ": not a material file, left out");
        } else {
            matches.push_back(m);
        }
    }
    if (matches.empty() && own_matched > 0)
        c.warnings.push_back(where + ": '" + pattern + "' matches only files the batch writes (" + std::to_string(own_matched) +
                             " left out: outputs, summaries, its work folder)");
    else if (matches.empty() && special == 0)
        c.warnings.push_back(where + ": '" + pattern + "' matches no file");
    return matches;
}

// The keys of a `defaults` or `materials.NAME` mapping: the settings but render.*, which nest
// under `render:`.
std::vector<std::string> settings_keys() {
    std::vector<std::string> keys = setting_names();
    keys.erase(std::remove_if(keys.begin(), keys.end(), [](const std::string& k) { return k.rfind("render.", 0) == 0; }),
               keys.end());
    return keys;
}

// An input: its path and where it was named.
struct Found {
    std::string path, origin;
};
using FoundInputs = std::map<std::string, Found>;  // by name

// The configuration's top-level keys but inputs, defaults and materials.
void read_top_level(const YAML::Node& root, const ConfigReader& rd, BatchConfig& c) {
    if (root["version"] && rd.scalar(root["version"], "version") != "1") rd.fail(root["version"], "version", "only version 1 is known");
    if (root["description"]) rd.scalar(root["description"], "description");
    if (!root["output_dir"]) throw Error(rd.source, "key 'output_dir' is required");
    c.output_dir = rd.path(root["output_dir"], "output_dir");
    if (root["naming"]) {
        c.naming = rd.scalar(root["naming"], "naming");
        if (c.naming.find("{name}") == std::string::npos) rd.fail(root["naming"], "naming", "must contain {name}");
        if (c.naming.find('/') != std::string::npos) rd.fail(root["naming"], "naming", "must not contain '/'");
        if (c.naming.size() < 5 || c.naming.compare(c.naming.size() - 4, 4, ".exr") != 0)
            rd.fail(root["naming"], "naming", "must end in .exr");
    }
    if (root["summary"]) c.summary = rd.path(root["summary"], "summary");
}

// The batch's own files (outputs, work folder, renders, summaries, this file) are never inputs:
// a glob over the output folder would otherwise convert the last run's outputs on every run.
void refuse_own(const OwnFiles& own, const ConfigReader& rd, const std::string& path, const YAML::Node& node, const std::string& key) {
    const std::string kind = own.kind(path);
    if (!kind.empty()) rd.fail(node, key, "'" + path + "' is " + kind + "; the batch's own files are never inputs");
}

// `inputs`: every path and glob, by name.
FoundInputs read_inputs(const YAML::Node& root, const ConfigReader& rd, const OwnFiles& own, BatchConfig& c) {
    if (!root["inputs"]) throw Error(rd.source, "key 'inputs' is required");
    const YAML::Node inputs = root["inputs"];
    if (!inputs.IsScalar() && !(inputs.IsSequence() && inputs.size() > 0))
        rd.fail(inputs, "inputs", "expected a path or glob, or a list of them");
    std::vector<YAML::Node> entries;
    if (inputs.IsScalar()) entries.push_back(inputs);
    else for (const YAML::Node& n : inputs) entries.push_back(n);
    FoundInputs found;
    std::set<std::string> seen_paths;
    const auto add = [&](const std::string& path, const YAML::Node& node) {
        if (!seen_paths.insert(path).second) return;
        const std::string name = stem_of(path);
        if (name.empty()) rd.fail(node, "inputs", "'" + path + "' has no file name");
        const auto [it, fresh] = found.emplace(name, Found{path, rd.where(node)});
        if (!fresh) {
            rd.fail(node, "inputs", "two inputs are named '" + name + "': " + it->second.path + " (" + it->second.origin + ") and " +
                                        path + "; rename one or list it under materials with its own input");
        }
    };
    for (const YAML::Node& n : entries) {
        const std::string pattern = rd.path(n, "inputs");
        if (has_wildcard(pattern)) {
            for (const std::string& m : glob_materials(pattern, rd.where(n), own, c)) add(m, n);
        } else {
            refuse_own(own, rd, pattern, n, "inputs");
            add(pattern, n);
        }
    }
    return found;
}

// `materials`: each entry's settings (into `overrides`), its own input (into `found`) and skip.
void read_materials(const YAML::Node& mats, const ConfigReader& rd, const OwnFiles& own, FoundInputs& found,
                    std::map<std::string, Settings>& overrides, std::set<std::string>& skipped) {
    if (!mats.IsMap()) rd.fail(mats, "materials", "expected a mapping from material names to settings");
    std::vector<std::string> material_keys = settings_keys();
    material_keys.push_back("input");
    material_keys.push_back("skip");
    std::set<std::string> seen;
    for (const auto& kv : mats) {
        if (!kv.first.IsScalar() || kv.first.Scalar().empty()) rd.fail(kv.first, "materials", "material names must be plain names");
        const std::string name = kv.first.Scalar();
        if (!seen.insert(name).second) rd.fail(kv.first, "materials." + name, "given twice");
        const std::string key = "materials." + name;
        if (kv.second.IsNull()) rd.fail(kv.first, key, "has no settings");
        rd.only(kv.second, key, material_keys);
        if (kv.second["input"]) {
            const std::string p = rd.path(kv.second["input"], key + ".input");
            refuse_own(own, rd, p, kv.second["input"], key + ".input");
            if (found.count(name)) {
                rd.fail(kv.second["input"], key + ".input",
                        "'" + name + "' is already an input (" + found[name].path + ", " + found[name].origin + ")");
            }
            found.emplace(name, Found{p, rd.where(kv.second["input"])});
        } else if (!found.count(name)) {
            rd.fail(kv.first, key, "no input is named '" + name + "' (names are the inputs' file names without extension)");
        }
        if (kv.second["skip"]) {
            const std::string v = rd.scalar(kv.second["skip"], key + ".skip");
            if (detail::boolean(rd.where(kv.second["skip"]), key + ".skip", v)) skipped.insert(name);
        }
        rd.settings(kv.second, key + ".", overrides[name]);
    }
}

BatchConfig parse_config(const std::string& yaml, const std::string& source, const std::string& base_dir, const std::string& config_path) {
    ConfigReader rd;
    rd.source = source;
    rd.base_dir = base_dir;
    rd.qualify_unknown_keys = true;
    const YAML::Node root = rd.load_mapping(yaml, "expected a mapping with output_dir, inputs and optionally defaults, materials");
    rd.only(root, "", {"version", "description", "output_dir", "naming", "summary", "inputs", "defaults", "materials"});

    BatchConfig c;
    c.path = config_path;
    c.base_dir = base_dir;
    read_top_level(root, rd, c);
    const OwnFiles own(c);
    FoundInputs found = read_inputs(root, rd, own, c);
    Settings defaults;
    if (root["defaults"]) {
        rd.only(root["defaults"], "defaults", settings_keys());
        rd.settings(root["defaults"], "defaults.", defaults);
    }
    std::map<std::string, Settings> overrides;
    std::set<std::string> skipped;
    if (root["materials"]) read_materials(root["materials"], rd, own, found, overrides, skipped);

    for (const auto& [name, f] : found) {
        if (skipped.count(name)) {
            c.skipped_by_config.push_back(name);
            continue;
        }
        MaterialJob job;
        job.name = name;
        job.input = f.path;
        job.origin = f.origin;
        job.output = (fs::path(c.output_dir) / detail::apply_naming(c.naming, name)).lexically_normal().string();
        job.settings = defaults;
        for (const auto& [k, v] : overrides[name]) job.settings[k] = v;
        c.materials.push_back(std::move(job));
    }
    // std::map keeps names sorted, so materials are in name order.
    return c;
}

}  // namespace

BatchConfig parse_batch_config(const std::string& yaml, const std::string& source, const std::string& base_dir) {
    return parse_config(yaml, source, base_dir, "");
}

BatchConfig load_batch_config(const std::string& path) {
    const std::string text = read_text_file(path, "a batch configuration", kConfigTextBounds);
    const fs::path abs = fs::absolute(path).lexically_normal();
    return parse_config(text, path, abs.parent_path().string(), abs.string());
}

}  // namespace npf::batch
