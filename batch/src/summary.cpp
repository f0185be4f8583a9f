#include <npf/batch/summary.h>

#include "figure_text.h"

#include <npf/converter/convert.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/core/json_text.h>
#include <npf/core/text.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

namespace npf::batch {

namespace {

std::string opt(const std::optional<double>& v) { return v ? json_number(*v) : "null"; }

using detail::decibels;
using detail::fixed;
using detail::megabytes;

// Markdown text on one line: control characters escaped (a newline in a file name would end
// a table row), and no pipes (they would end a cell).
std::string cell(const std::string& text) {
    std::string s = printable(text);
    std::replace(s.begin(), s.end(), '|', '/');
    return s;
}

MaterialStatus parse_status(const std::string& s, const std::string& path) {
    if (s == "converted") return MaterialStatus::Converted;
    if (s == "skipped") return MaterialStatus::Skipped;
    if (s == "failed") return MaterialStatus::Failed;
    throw Error(path, "unknown material status '" + s + "'");
}

}  // namespace

const char* status_name(MaterialStatus s) {
    switch (s) {
    case MaterialStatus::Converted: return "converted";
    case MaterialStatus::Skipped: return "skipped";
    case MaterialStatus::Failed: return "failed";
    }
    return "?";
}

void MaterialResult::judge_by_worst_lighting() {
    const LightingCheck* worst = nullptr;
    for (const LightingCheck& c : lightings)
        if (!worst || c.psnr < worst->psnr) worst = &c;
    if (!worst) return;
    psnr = worst->psnr, psnr_floor = worst->psnr_floor, ssim = worst->ssim, relmse = worst->relmse;
}

std::optional<double> MaterialResult::ratio() const {
    if (input_bytes == 0 || output_bytes == 0) return std::nullopt;
    return double(input_bytes) / double(output_bytes);
}

std::size_t BatchSummary::count(MaterialStatus s) const {
    return std::size_t(std::count_if(materials.begin(), materials.end(), [s](const MaterialResult& m) { return m.status == s; }));
}

std::string summary_json(const BatchSummary& s) {
    std::string j = "{\n";
    j += "  \"npf_batch_summary\": 1,\n";
    j += "  \"config\": " + json_string(s.config) + ",\n";
    j += "  \"shard_index\": " + std::to_string(s.shard_index) + ",\n";
    j += "  \"shard_count\": " + std::to_string(s.shard_count) + ",\n";
    j += "  \"shards\": [";
    for (std::size_t i = 0; i < s.shards.size(); ++i) j += (i ? ", " : "") + std::to_string(s.shards[i]);
    j += "],\n";
    j += "  \"config_materials\": " + std::to_string(s.config_materials) + ",\n";
    j += "  \"seconds\": " + json_number(s.seconds) + ",\n";
    j += "  \"counts\": {\"converted\": " + std::to_string(s.count(MaterialStatus::Converted)) +
         ", \"skipped\": " + std::to_string(s.count(MaterialStatus::Skipped)) +
         ", \"failed\": " + std::to_string(s.count(MaterialStatus::Failed)) + "},\n";
    j += "  \"ok\": " + std::string(s.ok() ? "true" : "false") + ",\n";
    // A line each: a reader's line cap (kSummaryTextBounds) bounds one warning, not all of them.
    j += "  \"warnings\": [";
    for (std::size_t i = 0; i < s.warnings.size(); ++i) j += (i ? ",\n    " : "\n    ") + json_string(s.warnings[i]);
    j += s.warnings.empty() ? "],\n" : "\n  ],\n";
    j += "  \"materials\": [";
    for (std::size_t i = 0; i < s.materials.size(); ++i) {
        const MaterialResult& m = s.materials[i];
        j += i ? ",\n    {" : "\n    {";
        j += "\"name\": " + json_string(m.name) + ", \"status\": " + json_string(status_name(m.status));
        j += ", \"reason\": " + json_string(m.reason);
        j += ", \"input\": " + json_string(m.input) + ", \"output\": " + json_string(m.output);
        j += ", \"shard\": " + std::to_string(m.shard) + ", \"seconds\": " + json_number(m.seconds);
        j += ", \"input_bytes\": " + std::to_string(m.input_bytes) + ", \"output_bytes\": " + std::to_string(m.output_bytes);
        j += ", \"ratio\": " + opt(m.ratio());
        j += ", \"error_rel_rms_mean\": " + opt(m.error_mean) + ", \"error_rel_rms_max\": " + opt(m.error_max);
        j += ", \"fitted_error_rel_rms_mean\": " + opt(m.fitted_error_mean) +
             ", \"fitted_error_rel_rms_max\": " + opt(m.fitted_error_max);
        j += ", \"albedo_max\": " + opt(m.albedo_max);
        j += ", \"psnr\": " + opt(m.psnr) + ", \"psnr_floor\": " + opt(m.psnr_floor) + ", \"ssim\": " + opt(m.ssim) +
             ", \"relmse\": " + opt(m.relmse);
        j += ", \"lightings\": [";
        for (std::size_t l = 0; l < m.lightings.size(); ++l) {
            const LightingCheck& c = m.lightings[l];
            j += std::string(l ? ", " : "") + "{\"lighting\": " + json_string(c.lighting) + ", \"psnr\": " + json_number(c.psnr) +
                 ", \"psnr_floor\": " + json_number(c.psnr_floor) + ", \"ssim\": " + json_number(c.ssim) +
                 ", \"relmse\": " + json_number(c.relmse) + "}";
        }
        j += "]";
        j += ", \"edits\": [";
        for (std::size_t e = 0; e < m.edits.size(); ++e) j += (e ? ", " : "") + json_string(m.edits[e]);
        j += "], \"hash\": " + json_string(m.hash) + "}";
    }
    j += s.materials.empty() ? "]\n}\n" : "\n  ]\n}\n";
    return j;
}

std::string summary_markdown(const BatchSummary& s) {
    std::string md = "# npf batch summary\n\n";
    md += "- configuration: `" + cell(s.config) + "`\n";
    if (s.shards.size() == 1) {
        md += "- shard: " + std::to_string(s.shard_index) + " of " + std::to_string(s.shard_count) + "\n";
    } else {
        md += "- shards merged: " + std::to_string(s.shards.size()) + " of " + std::to_string(s.shard_count) + "\n";
    }
    md += "- materials: " + std::to_string(s.materials.size()) + " (" + std::to_string(s.count(MaterialStatus::Converted)) +
          " converted, " + std::to_string(s.count(MaterialStatus::Skipped)) + " skipped, " +
          std::to_string(s.count(MaterialStatus::Failed)) + " failed) of " + std::to_string(s.config_materials) +
          " in the configuration\n";
    md += "- wall time: " + fixed(s.seconds, 2) + " s\n";
    md += std::string("- result: ") + (s.ok() ? "**ok**" : "**some materials failed**") + "\n";
    for (const std::string& w : s.warnings) md += "- warning: " + cell(w) + "\n";
    md += "\n| material | status | time (s) | input (MB) | output (MB) | ratio | error mean / worst (%) | PSNR, worst lighting (dB) | noise floor (dB) | SSIM | per lighting: PSNR / floor (dB) | note |\n";
    md += "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|\n";
    for (const MaterialResult& m : s.materials) {
        md += "| " + cell(m.name) + " | " + status_name(m.status) + " | " + fixed(m.seconds, 2) + " | ";
        md += (m.input_bytes ? megabytes(m.input_bytes) : "-") + " | " + (m.output_bytes ? megabytes(m.output_bytes) : "-") + " | ";
        md += (m.ratio() ? "1/" + fixed(*m.ratio(), 1) : "-") + " | ";
        md += (m.error_mean ? fixed(100.0 * *m.error_mean, 2) + " / " + fixed(100.0 * m.error_max.value_or(0.0), 2) : "-") + " | ";
        md += (m.psnr ? decibels(*m.psnr) : "-") + " | ";
        md += (m.psnr_floor ? decibels(*m.psnr_floor) : "-") + " | ";
        md += (m.ssim ? fixed(*m.ssim, 4) : "-") + " | ";
        std::string each;
        for (const LightingCheck& c : m.lightings)
            each += (each.empty() ? "" : ", ") + c.lighting + " " + decibels(c.psnr) + " / " + decibels(c.psnr_floor);
        md += cell(each.empty() ? "-" : each) + " | ";
        std::string note = m.reason;
        if (!m.edits.empty()) note += (note.empty() ? "" : "; ") + std::to_string(m.edits.size()) + " edit(s)";
        if (m.albedo_max && *m.albedo_max > kGainsLightAlbedo)
            note += (note.empty() ? "" : "; ") + std::string("albedo ") + fixed(*m.albedo_max, 3) + " > 1: gains light (npf albedo)";
        md += cell(note) + " |\n";
    }
    return md;
}

void write_summary(const BatchSummary& s, const std::string& base, const std::string& owned_by) {
    const std::string json = summary_json(s), md = summary_markdown(s);
    write_file_atomically(base + ".json", json.data(), json.size(), OutputOptions{owned_by, ""});
    write_file_atomically(base + ".md", md.data(), md.size(), OutputOptions{owned_by, ""});
}

BatchSummary read_summary_json(const std::string& path) {
    return parse_summary_json(read_text_file(path, "an npf batch summary", kSummaryTextBounds), path);
}

BatchSummary parse_summary_json(const std::string& text, const std::string& path) {
    YAML::Node root;
    try {
        root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
        throw Error(e.mark.line >= 0 ? path + ":" + std::to_string(e.mark.line + 1) : path, "not a batch summary: " + e.msg);
    }
    try {
        if (!root.IsMap() || !root["npf_batch_summary"] || root["npf_batch_summary"].as<int>() != 1)
            throw Error(path, "not an npf batch summary (version 1)");
        BatchSummary s;
        s.config = root["config"].as<std::string>();
        s.shard_index = root["shard_index"].as<int>();
        s.shard_count = root["shard_count"].as<int>();
        for (const YAML::Node& n : root["shards"]) s.shards.push_back(n.as<int>());
        s.config_materials = root["config_materials"].as<std::size_t>();
        s.seconds = root["seconds"].IsNull() ? 0.0 : root["seconds"].as<double>();
        for (const YAML::Node& n : root["warnings"]) s.warnings.push_back(n.as<std::string>());
        const auto optional = [](const YAML::Node& n) -> std::optional<double> {
            if (!n || n.IsNull()) return std::nullopt;
            return n.as<double>();
        };
        for (const YAML::Node& n : root["materials"]) {
            MaterialResult m;
            m.name = n["name"].as<std::string>();
            m.status = parse_status(n["status"].as<std::string>(), path);
            m.reason = n["reason"].as<std::string>();
            m.input = n["input"].as<std::string>();
            m.output = n["output"].as<std::string>();
            m.shard = n["shard"].as<int>();
            m.seconds = optional(n["seconds"]).value_or(0.0);
            m.input_bytes = n["input_bytes"].as<std::uint64_t>();
            m.output_bytes = n["output_bytes"].as<std::uint64_t>();
            m.error_mean = optional(n["error_rel_rms_mean"]);
            m.error_max = optional(n["error_rel_rms_max"]);
            m.fitted_error_mean = optional(n["fitted_error_rel_rms_mean"]);
            m.fitted_error_max = optional(n["fitted_error_rel_rms_max"]);
            m.albedo_max = optional(n["albedo_max"]);
            m.psnr = optional(n["psnr"]);
            m.psnr_floor = optional(n["psnr_floor"]);
            m.ssim = optional(n["ssim"]);
            m.relmse = optional(n["relmse"]);
            // Summaries before issue 34 have no per-lighting figures.
            const double inf = std::numeric_limits<double>::infinity();
            for (const YAML::Node& l : n["lightings"]) {
                m.lightings.push_back({l["lighting"].as<std::string>(), optional(l["psnr"]).value_or(inf),
                                       optional(l["psnr_floor"]).value_or(inf), optional(l["ssim"]).value_or(1.0),
                                       optional(l["relmse"]).value_or(0.0)});
            }
            for (const YAML::Node& e : n["edits"]) m.edits.push_back(e.as<std::string>());
            m.hash = n["hash"].as<std::string>();
            s.materials.push_back(std::move(m));
        }
        return s;
    } catch (const Error&) {
        throw;
    } catch (const YAML::Exception& e) {
        throw Error(path, "malformed batch summary: " + e.msg);
    }
}

BatchSummary merge_summaries(const std::vector<BatchSummary>& parts) {
    if (parts.empty()) throw Error("merge", "no summaries to merge");
    BatchSummary out;
    out.config = parts.front().config;
    out.shard_count = parts.front().shard_count;
    out.shard_index = -1;
    out.config_materials = parts.front().config_materials;
    std::map<std::string, MaterialResult> by_name;
    std::set<int> shards;
    for (const BatchSummary& p : parts) {
        if (p.config != out.config) out.warnings.push_back("summary of another configuration merged: " + p.config);
        if (p.shard_count != out.shard_count)
            out.warnings.push_back("summaries of different shard counts merged (" + std::to_string(p.shard_count) + " and " +
                                   std::to_string(out.shard_count) + ")");
        for (int k : p.shards) {
            if (!shards.insert(k).second) out.warnings.push_back("shard " + std::to_string(k) + " given twice");
        }
        out.seconds += p.seconds;
        for (const std::string& w : p.warnings) {
            if (std::find(out.warnings.begin(), out.warnings.end(), w) == out.warnings.end()) out.warnings.push_back(w);
        }
        for (const MaterialResult& m : p.materials) {
            if (by_name.count(m.name)) out.warnings.push_back("material '" + m.name + "' reported by more than one shard");
            by_name[m.name] = m;
        }
    }
    for (int k = 0; k < out.shard_count; ++k) {
        if (!shards.count(k)) out.warnings.push_back("shard " + std::to_string(k) + " of " + std::to_string(out.shard_count) + " is missing");
    }
    out.shards.assign(shards.begin(), shards.end());
    for (auto& [name, m] : by_name) out.materials.push_back(std::move(m));
    if (out.materials.size() < out.config_materials) {
        out.warnings.push_back(std::to_string(out.config_materials - out.materials.size()) + " material(s) of the configuration not reported");
    }
    return out;
}

}  // namespace npf::batch
