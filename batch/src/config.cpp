// Batch configuration: parsing, checking and the settings -> ConvertSettings mapping.
#include <npf/batch/config.h>
#include <npf/core/atomic_file.h>

#include <npf/core/channels.h>
#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/core/text.h>
#include <npf/core/text_input.h>

#include <npf/converter/convert_settings_table.h>
#include <npf/materials/yaml_context.h>
#include <npf/render/lighting.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <limits>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <glob.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <optional>
#include <set>

namespace npf::batch {

namespace fs = std::filesystem;

namespace {

// ---- values: text -> checked value (shared by parsing and resolving) -------------------------

[[noreturn]] void bad(const std::string& origin, const std::string& key, const std::string& problem) {
    throw Error(origin, "key '" + key + "': " + problem);
}

long whole(const std::string& origin, const std::string& key, const std::string& v, long lo, long hi) {
    try {
        return long(parse_whole_number(v, std::uint64_t(lo), std::uint64_t(hi), key));
    } catch (const Error& e) {
        bad(origin, key, e.problem());
    }
}

bool boolean(const std::string& origin, const std::string& key, const std::string& v) {
    if (v == "true") return true;
    if (v == "false") return false;
    bad(origin, key, "expects true or false, got '" + v + "'");
}

// Checks a value of setting `setting` as resolve_convert_settings and resolve_render_check will
// read it; errors call it `key` (the name as written: "defaults.preset").
void check_value(const std::string& origin, const std::string& key, const std::string& setting, const std::string& v) {
    const std::string& k = setting;
    if (const ConvertSettingRow* row = find_setting(convert_settings_table(), k)) {
        try {
            check_setting(*row, v, key);
        } catch (const Error& e) {
            bad(origin, key, e.problem());
        }
        return;
    }
    if (k == "render") boolean(origin, key, v);
    else if (k == "render.threads") whole(origin, key, v, 1, 1024);
    // The renderer's own bounds, as `npf render`'s.
    else if (k == "render.size") whole(origin, key, v, 1, long(render::RenderOptions::kMaxSide));
    else if (k == "render.spp") whole(origin, key, v, 1, long(render::RenderOptions::kMaxSpp));
    else if (k == "render.seed") whole(origin, key, v, 0, std::numeric_limits<long>::max());
    else if (k == "memory_limit" || k == "time_limit") {
        try {
            if (k == "memory_limit") parse_memory_limit(v, key);
            else parse_time_limit(v, key);
        } catch (const Error& e) {
            bad(origin, key, e.problem());
        }
    }
    // edit and render.env are paths, checked when used.
}

// ---- YAML reading ---------------------------------------------------------------------------

// Unknown keys are named with their parent ("defaults.presett"): settings nest.
struct Reader : YamlContext {
    std::string scalar(const YAML::Node& node, const std::string& key) const {
        if (!node.IsScalar()) fail(node, key, "expected a single value");
        return node.Scalar();
    }
    std::string path(const YAML::Node& node, const std::string& key) const {
        const std::string p = scalar(node, key);
        if (p.empty()) fail(node, key, "empty path");
        if (p.find('\0') != std::string::npos) fail(node, key, "path holds a NUL byte");
        return absolute(p);
    }
    std::string absolute(const std::string& p) const {
        const fs::path q(p);
        return (q.is_absolute() ? q : fs::path(base_dir) / q).lexically_normal().string();
    }
    // A scalar or a sequence of scalars joined by commas ("[90, 1, 90, 180]" -> "90,1,90,180").
    std::string list(const YAML::Node& node, const std::string& key) const {
        if (node.IsScalar()) {
            std::string v = node.Scalar();
            v.erase(std::remove(v.begin(), v.end(), ' '), v.end());
            return v;
        }
        if (!node.IsSequence() || node.size() == 0) fail(node, key, "expected a value or a list of values");
        std::string out;
        for (const YAML::Node& item : node) out += (out.empty() ? "" : ",") + scalar(item, key);
        return out;
    }

    // A lighting or a list of them ("key-rim", "[studio, maps/dusk.exr]", "studio,directional"):
    // built-in names (render/lighting.h) as they are, map files from the configuration's folder.
    std::string lightings(const YAML::Node& node, const std::string& key) const {
        const std::vector<std::string>& names = render::builtin_lighting_names();
        // Items as written (a map's path may hold blanks), trimmed.
        std::vector<std::string> items;
        if (node.IsSequence() && node.size() > 0) {
            for (const YAML::Node& item : node) items.push_back(scalar(item, key));
        } else {
            const std::string given = scalar(node, key);
            for (std::size_t start = 0; start <= given.size();) {
                const std::size_t comma = std::min(given.find(',', start), given.size());
                items.push_back(given.substr(start, comma - start));
                start = comma + 1;
            }
        }
        std::string out;
        for (std::string item : items) {
            const std::size_t a = item.find_first_not_of(" \t"), b = item.find_last_not_of(" \t");
            item = a == std::string::npos ? "" : item.substr(a, b - a + 1);
            if (item.empty()) fail(node, key, "an empty lighting in the list");
            if (item.find('\0') != std::string::npos) fail(node, key, "path holds a NUL byte");
            if (std::find(names.begin(), names.end(), item) == names.end()) item = absolute(item);
            out += (out.empty() ? "" : ",") + item;
        }
        try {
            render::parse_lighting_list(out, key);  // each a name or an existing file, none twice
        } catch (const Error& e) {
            fail(node, key, e.problem());
        }
        return out;
    }

    // Settings of a `defaults` or `materials.NAME` mapping (other keys are left to the caller).
    void settings(const YAML::Node& map, const std::string& prefix, Settings& out) const {
        for (const auto& kv : map) {
            const std::string k = kv.first.Scalar();
            if (k == "input" || k == "skip") continue;
            const std::string origin = where(kv.first);
            const std::string full = prefix + k;
            if (k == "edit") {
                const YAML::Node& v = kv.second;
                if (v.IsScalar() && (v.Scalar() == "false" || v.Scalar() == "none")) out[k] = {"", origin};
                else out[k] = {path(v, full), origin};
            } else if (k == "render") {
                const YAML::Node& v = kv.second;
                if (v.IsScalar()) {
                    check_value(origin, full, "render", v.Scalar());
                    out[k] = {v.Scalar(), origin};
                    continue;
                }
                only(v, full, {"size", "spp", "seed", "env", "threads"});
                out[k] = {"true", origin};
                for (const auto& r : v) {
                    const std::string rk = r.first.Scalar(), name = "render." + rk;
                    const std::string ro = where(r.first);
                    if (rk == "env") {
                        out[name] = {lightings(r.second, full + "." + rk), ro};
                    } else {
                        const std::string value = scalar(r.second, full + "." + rk);
                        check_value(ro, full + "." + rk, name, value);
                        out[name] = {value, ro};
                    }
                }
            } else {
                const ConvertSettingRow* row = find_setting(convert_settings_table(), k);
                const std::string value = row && row->takes_list ? list(kv.second, full) : scalar(kv.second, full);
                check_value(origin, full, k, value);
                out[k] = {value, origin};
            }
        }
    }
};

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

bool starts_with(const std::string& s, const std::string& p) { return s.size() >= p.size() && s.compare(0, p.size(), p) == 0; }

// A path with its symbolic links resolved as far as it exists, so that a folder reached two ways
// is recognised (the lexical path when that fails).
fs::path resolved(const std::string& path) {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(fs::path(path), ec);
    return ec ? fs::path(path).lexically_normal() : p;
}

bool is_under(const fs::path& p, const fs::path& dir) {
    auto d = dir.begin(), q = p.begin();
    for (; d != dir.end(); ++d, ++q) {
        if (q == p.end() || *q != *d) return false;
    }
    return q != p.end();
}

// `naming` with `name` put in for every {name}. One pass over `naming`: a name that itself holds
// "{name}" (an input file may be called so) is not expanded again (fuzzing found the loop).
std::string apply_naming(const std::string& naming, const std::string& name) {
    std::string out;
    std::size_t from = 0;
    for (std::size_t at; (at = naming.find("{name}", from)) != std::string::npos; from = at + 6) {
        out.append(naming, from, at - from).append(name);
    }
    return out.append(naming, from, std::string::npos);
}

// Whether `file` is `naming` with one name put in for every {name}.
bool fits_naming(const std::string& file, const std::string& naming) {
    std::size_t fixed = naming.size(), count = 0;
    for (std::size_t at = naming.find("{name}"); at != std::string::npos; at = naming.find("{name}", at + 6)) fixed -= 6, ++count;
    if (count == 0 || file.size() <= fixed || (file.size() - fixed) % count != 0) return false;
    const std::size_t first = naming.find("{name}");
    const std::string name = file.substr(first, (file.size() - fixed) / count);
    return apply_naming(naming, name) == file;
}

// A summary by its first bytes (summary_json and summary_markdown begin so), wherever it was
// written: --summary, shard summaries, merged ones.
bool is_summary_file(const fs::path& p) {
    const std::string ext = p.extension().string();
    if (ext != ".json" && ext != ".md") return false;
    // A regular file only, opened without waiting: a FIFO named x.json would hold the open.
    const int fd = ::open(p.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return false;
    struct stat st {};
    char head[64] = {};
    ssize_t got = -1;
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) got = ::read(fd, head, sizeof head);
    ::close(fd);
    std::string text(head, got > 0 ? std::size_t(got) : 0);
    text.erase(std::remove_if(text.begin(), text.end(), [](char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }),
               text.end());
    return starts_with(text, "{\"npf_batch_summary\"") || starts_with(text, "#npfbatchsummary");
}

// Everything the batch writes or owns, resolved once per configuration.
class OwnFiles {
public:
    explicit OwnFiles(const BatchConfig& c)
        : m_out(resolved(c.output_dir)), m_naming(c.naming),
          m_summary(resolved(c.summary.empty() ? (fs::path(c.output_dir) / "batch-summary").string() : c.summary)),
          m_config(c.path.empty() ? fs::path() : resolved(c.path)) {}

    std::string kind(const std::string& path) const {
        // The folder resolved, the name kept: a link at an output's name is still an output.
        const fs::path given = fs::path(path).lexically_normal();
        const fs::path p = resolved(given.parent_path().string()) / given.filename();
        if (is_under(p, m_out / ".npf-batch")) return "in the batch's work folder (.npf-batch)";
        if (is_under(p, m_out / "renders")) return "a validation render of the batch";
        const std::string file = p.filename().string();
        if (p.parent_path() == m_out && fits_naming(file, m_naming)) return "an output of the batch (naming '" + m_naming + "')";
        const std::size_t tmp = file.rfind(kTemporarySuffix);
        if (p.parent_path() == m_out && tmp != std::string::npos && is_temporary_of(file, file.substr(0, tmp)) &&
            fits_naming(file.substr(0, tmp), m_naming))
            return "an unfinished output of the batch (a temporary file left by a killed run)";
        const std::string base = m_summary.filename().string();
        if (p.parent_path() == m_summary.parent_path() &&
            (file == base + ".json" || file == base + ".md" ||
             (starts_with(file, base + ".shard-") && (ends_with(file, ".json") || ends_with(file, ".md")))))
            return "the batch's summary";
        if (!m_config.empty() && (p == m_config || resolved(path) == m_config)) return "the batch's configuration";
        if (is_summary_file(p)) return "an npf batch summary";
        return "";
    }

private:
    fs::path m_out;
    std::string m_naming;
    fs::path m_summary, m_config;
};

std::vector<std::string> settings_keys() {
    std::vector<std::string> keys = setting_names();
    keys.erase(std::remove_if(keys.begin(), keys.end(), [](const std::string& k) { return k.rfind("render.", 0) == 0; }),
               keys.end());
    return keys;
}

}  // namespace

const std::vector<std::string>& setting_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const ConvertSettingRow& row : convert_settings_table()) n.push_back(row.key);
        for (const char* batch_only : {"memory_limit", "time_limit", "edit", "render", "render.size", "render.spp", "render.seed",
                                       "render.env", "render.threads"}) {
            n.emplace_back(batch_only);
        }
        return n;
    }();
    return names;
}

ConvertSettings resolve_convert_settings(const Settings& s, bool source_isotropic) {
    for (const auto& [k, v] : s) check_value(v.origin, k, k, v.value);
    const ConvertSettingsTable& table = convert_settings_table();
    try {
        return resolve_convert_settings(
            table,
            [&](const ConvertSettingRow& row) -> std::optional<SettingValue> {
                const auto it = s.find(row.key);
                if (it == s.end()) return std::nullopt;
                return check_setting(row, it->second.value, row.key);
            },
            [](const ConvertSettingRow& row) { return row.key; }, source_isotropic);
    } catch (const Error& e) {
        // Settings that do not go together: named by the first one's origin and key.
        const auto it = s.find(e.source());
        if (it == s.end()) throw;
        bad(it->second.origin, it->first, e.problem());
    }
}

RenderCheck resolve_render_check(const Settings& s) {
    RenderCheck r;
    const auto it = s.find("render");
    r.enabled = it != s.end() && it->second.value == "true";
    // Checked when read (check_value); read here by the same parser.
    const auto whole_of = [&s](const char* key, std::uint64_t fallback) {
        const auto i = s.find(key);
        return i == s.end() ? fallback : parse_whole_number(i->second.value, 0, std::numeric_limits<std::uint64_t>::max(), key);
    };
    r.size = std::size_t(whole_of("render.size", r.size));
    r.spp = std::uint32_t(whole_of("render.spp", r.spp));
    r.seed = whole_of("render.seed", r.seed);
    r.threads = unsigned(whole_of("render.threads", r.threads));
    if (const auto i = s.find("render.env"); i != s.end()) r.lightings = render::parse_lighting_list(i->second.value, "render.env");
    else if (const auto l = s.find("light"); l != s.end()) r.lightings = render::parse_lighting_list(l->second.value, "light");
    else r.lightings = render::builtin_lighting_names();
    return r;
}

namespace {

std::string trimmed(const std::string& v) {
    const std::size_t a = v.find_first_not_of(" \t"), b = v.find_last_not_of(" \t");
    return a == std::string::npos ? std::string() : v.substr(a, b - a + 1);
}

// The number a value starts with, and the rest (trimmed); false when it does not start with one.
bool number_and_unit(const std::string& v, double& number, std::string& unit) {
    const std::string t = trimmed(v);
    if (t.empty() || !(std::isdigit(static_cast<unsigned char>(t[0])) || t[0] == '.')) return false;
    char* end = nullptr;
    number = std::strtod(t.c_str(), &end);
    unit = trimmed(end);
    return end != t.c_str() && std::isfinite(number);
}


}  // namespace

std::uint64_t parse_memory_limit(const std::string& text, const std::string& what) {
    if (lowercase(trimmed(text)) == "none") return 0;
    double n = 0;
    std::string unit;
    const auto fail = [&](const std::string& problem) -> std::uint64_t { throw Error(what, problem + ", got '" + text + "'"); };
    if (!number_and_unit(text, n, unit)) return fail("expects a size such as 8 GiB, 512 MiB or none");
    const std::string u = lowercase(unit);
    static const std::pair<const char*, int> units[] = {{"k", 1}, {"m", 2}, {"g", 3}, {"t", 4}};
    int power = -1;
    for (const auto& [name, p] : units) {
        const std::string b = name;
        if (u == b || u == b + "b" || u == b + "ib") power = p;
    }
    if (power < 0) return fail("needs a unit: K, M, G or T (powers of 1024, as KiB, MiB, GiB, TiB)");
    const double bytes = n * std::pow(1024.0, power);
    if (!(bytes >= double(64u << 20))) return fail("must be at least 64 MiB (or none)");
    if (!(bytes <= std::ldexp(1.0, 62))) return fail("is too large (or use none)");
    return std::uint64_t(bytes);
}

double parse_time_limit(const std::string& text, const std::string& what) {
    if (lowercase(trimmed(text)) == "none") return 0.0;
    double n = 0;
    std::string unit;
    if (!number_and_unit(text, n, unit)) throw Error(what, "expects seconds, or a time such as 90 s, 30 min, 6 h, or none, got '" + text + "'");
    const std::string u = lowercase(unit);
    double scale = 0;
    if (u.empty() || u == "s" || u == "sec" || u == "seconds") scale = 1;
    else if (u == "min" || u == "minutes") scale = 60;
    else if (u == "h" || u == "hours") scale = 3600;
    if (scale == 0) throw Error(what, "unit '" + unit + "' is not one of s, min, h, got '" + text + "'");
    const double seconds = n * scale;
    if (!(seconds > 0.0 && seconds <= 1e9)) throw Error(what, "must be above 0 (or none), got '" + text + "'");
    return seconds;
}

std::string describe_memory(std::uint64_t bytes) {
    if (bytes == 0) return "none";
    static const char* names[] = {"KiB", "MiB", "GiB", "TiB"};
    int i = 3;
    while (i > 0 && double(bytes) < std::ldexp(1.0, 10 * (i + 1))) --i;
    return number_text(double(bytes) / std::ldexp(1.0, 10 * (i + 1)), 4) + " " + names[i];
}

std::string describe_seconds(double seconds) {
    if (seconds <= 0.0) return "none";
    char b[40];
    std::snprintf(b, sizeof b, "%g s", seconds);
    return b;
}

MaterialLimits resolve_limits(const Settings& s) {
    MaterialLimits l;
    if (const auto i = s.find("memory_limit"); i != s.end()) l.memory_bytes = parse_memory_limit(i->second.value, i->second.origin);
    if (const auto i = s.find("time_limit"); i != s.end()) l.seconds = parse_time_limit(i->second.value, i->second.origin);
    return l;
}

std::string batch_file_kind(const BatchConfig& config, const std::string& path) { return OwnFiles(config).kind(path); }

std::string canonical_settings(const Settings& settings) {
    std::string text;
    for (const auto& [k, v] : settings) {
        const ConvertSettingRow* row = find_setting(convert_settings_table(), k);
        if ((row && !row->changes_output) || k == "memory_limit" || k == "time_limit" || k == "edit" || k == "render" ||
            k.rfind("render.", 0) == 0)
            continue;
        text += k + "=" + v.value + "\n";
    }
    return text;
}

namespace {

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

BatchConfig parse_config(const std::string& yaml, const std::string& source, const std::string& base_dir, const std::string& config_path) {
    Reader rd;
    rd.source = source;
    rd.base_dir = base_dir;
    rd.qualify_unknown_keys = true;
    YAML::Node root;
    try {
        root = YAML::Load(yaml);
    } catch (const YAML::Exception& e) {
        throw Error(e.mark.line >= 0 ? source + ":" + std::to_string(e.mark.line + 1) : source, "YAML: " + e.msg);
    }
    if (!root.IsMap()) throw Error(source, "expected a mapping with output_dir, inputs and optionally defaults, materials");
    rd.only(root, "", {"version", "description", "output_dir", "naming", "summary", "inputs", "defaults", "materials"});

    BatchConfig c;
    c.path = config_path;
    c.base_dir = base_dir;
    if (root["version"] && rd.scalar(root["version"], "version") != "1") rd.fail(root["version"], "version", "only version 1 is known");
    if (root["description"]) rd.scalar(root["description"], "description");
    if (!root["output_dir"]) throw Error(source, "key 'output_dir' is required");
    c.output_dir = rd.path(root["output_dir"], "output_dir");
    if (root["naming"]) {
        c.naming = rd.scalar(root["naming"], "naming");
        if (c.naming.find("{name}") == std::string::npos) rd.fail(root["naming"], "naming", "must contain {name}");
        if (c.naming.find('/') != std::string::npos) rd.fail(root["naming"], "naming", "must not contain '/'");
        if (c.naming.size() < 5 || c.naming.compare(c.naming.size() - 4, 4, ".exr") != 0)
            rd.fail(root["naming"], "naming", "must end in .exr");
    }
    if (root["summary"]) c.summary = rd.path(root["summary"], "summary");
    // The batch's own files (outputs, work folder, renders, summaries, this file) are never inputs:
    // a glob over the output folder would otherwise convert the last run's outputs on every run.
    const OwnFiles own(c);
    const auto refuse_own = [&](const std::string& path, const YAML::Node& node, const std::string& key) {
        const std::string kind = own.kind(path);
        if (!kind.empty()) rd.fail(node, key, "'" + path + "' is " + kind + "; the batch's own files are never inputs");
    };

    // Inputs: name -> (path, origin).
    if (!root["inputs"]) throw Error(source, "key 'inputs' is required");
    const YAML::Node inputs = root["inputs"];
    if (!inputs.IsScalar() && !(inputs.IsSequence() && inputs.size() > 0))
        rd.fail(inputs, "inputs", "expected a path or glob, or a list of them");
    std::vector<YAML::Node> entries;
    if (inputs.IsScalar()) entries.push_back(inputs);
    else for (const YAML::Node& n : inputs) entries.push_back(n);
    struct Found { std::string path, origin; };
    std::map<std::string, Found> found;
    std::set<std::string> seen_paths;
    const auto add = [&](const std::string& name, const std::string& path, const std::string& origin, const YAML::Node& node,
                         const std::string& key) {
        if (name.empty()) rd.fail(node, key, "'" + path + "' has no file name");
        const auto [it, fresh] = found.emplace(name, Found{path, origin});
        if (!fresh) {
            rd.fail(node, key, "two inputs are named '" + name + "': " + it->second.path + " (" + it->second.origin + ") and " +
                                   path + "; rename one or list it under materials with its own input");
        }
    };
    for (const YAML::Node& n : entries) {
        const std::string pattern = rd.path(n, "inputs");
        if (has_wildcard(pattern)) {
            for (const std::string& m : glob_materials(pattern, rd.where(n), own, c)) {
                if (seen_paths.insert(m).second) add(stem_of(m), m, rd.where(n), n, "inputs");
            }
        } else {
            refuse_own(pattern, n, "inputs");
            if (seen_paths.insert(pattern).second) add(stem_of(pattern), pattern, rd.where(n), n, "inputs");
        }
    }

    Settings defaults;
    std::vector<std::string> keys = settings_keys();
    if (root["defaults"]) {
        rd.only(root["defaults"], "defaults", keys);
        rd.settings(root["defaults"], "defaults.", defaults);
    }
    std::map<std::string, Settings> overrides;
    std::set<std::string> skipped;
    if (root["materials"]) {
        const YAML::Node mats = root["materials"];
        if (!mats.IsMap()) rd.fail(mats, "materials", "expected a mapping from material names to settings");
        std::vector<std::string> material_keys = keys;
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
                refuse_own(p, kv.second["input"], key + ".input");
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
                if (boolean(rd.where(kv.second["skip"]), key + ".skip", v)) skipped.insert(name);
            }
            rd.settings(kv.second, key + ".", overrides[name]);
        }
    }

    for (const auto& [name, f] : found) {
        if (skipped.count(name)) {
            c.skipped_by_config.push_back(name);
            continue;
        }
        MaterialJob job;
        job.name = name;
        job.input = f.path;
        job.origin = f.origin;
        job.output = (fs::path(c.output_dir) / apply_naming(c.naming, name)).lexically_normal().string();
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
