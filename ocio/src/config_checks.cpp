// The checks of config_checks.h: the YAML pre-pass, context variables and the transform graph,
// with the LUT files a display processor opens (the files themselves: config_lut_files.cpp; OCIO's
// reasons: config_reason.cpp). What OCIO 2.1 does that makes each necessary is
// noted where it is checked (sources: OpenColorIO v2.1.2, src/OpenColorIO/).
#include "config_checks.h"

#include <npf/color/display.h>
#include <npf/core/error.h>
#include <npf/core/text.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

namespace OCIO = OCIO_NAMESPACE;

namespace npf::color::detail {

namespace {


// YAML nesting with aliases expanded (yaml-cpp's parser stops at 2000 levels, but an alias
// can nest a whole earlier tree again). Real configs nest about ten levels.
constexpr int kMaxYamlDepth = 256;
// Context variable resolution: replacement passes and the length of what they produce, and the
// rounds (one variable over one string, one pass) for all of the config's strings: OCIO spends
// as many in validate() (4096 variables over 4096 references took it 2.5 s).
constexpr int kMaxResolvePasses = 16;
constexpr std::size_t kMaxResolvedBytes = std::size_t(1) << 16;
constexpr std::uint64_t kMaxResolveRounds = std::uint64_t(1) << 22;
// A file rule's pattern, extension or regex: OCIO compiles them with std::regex when it loads the
// config, and libstdc++'s regex compiler and matcher recurse per character (a regex of 20000
// nested parentheses overflowed the stack). Real rules are a few dozen characters.
constexpr std::size_t kMaxFileRuleBytes = 1024;

// ---------------------------------------------------------------------------------------------
// The YAML pre-pass

class YamlWalk {
public:
    explicit YamlWalk(const std::string& path) : m_path(path) {}

    void walk(const YAML::Node& node, int depth) {
        if (++m_nodes > kMaxConfigYamlNodes)
            throw Error(m_path, "its YAML expands to more than " + std::to_string(kMaxConfigYamlNodes) +
                                    " nodes (an alias counts as a copy of its anchor): refused");
        if (depth > kMaxYamlDepth)
            throw Error(m_path, "its YAML nests deeper than " + std::to_string(kMaxYamlDepth) + " levels" +
                                    at(node) + ": refused");
        if (node.IsSequence() || node.IsMap()) {
            if (node.size() > kMaxConfigListEntries)
                throw Error(m_path, "a YAML list or map" + at(node) + " has " + std::to_string(node.size()) +
                                        " entries, above npf's cap of " + std::to_string(kMaxConfigListEntries) +
                                        ": refused");
            for (const auto& item : node) {
                if (node.IsMap()) {
                    walk(item.first, depth + 1);
                    walk(item.second, depth + 1);
                } else {
                    walk(item, depth + 1);
                }
            }
        }
    }

private:
    static std::string at(const YAML::Node& node) {
        const int line = node.Mark().line;
        return line >= 0 ? " (line " + std::to_string(line + 1) + ")" : "";
    }

    const std::string& m_path;
    std::size_t m_nodes = 0;
};

bool is_sequence(const YAML::Node& node) { return node.IsDefined() && node.IsSequence(); }

// ---------------------------------------------------------------------------------------------
// Context variables

// StringUtils::ReplaceInPlace, stopping (false) once the result would pass `limit` bytes.
bool replace_all(std::string& s, const std::string& search, const std::string& value, std::size_t limit) {
    for (std::size_t at = s.find(search); at != std::string::npos; at = s.find(search, at)) {
        if (s.size() - search.size() + value.size() > limit) return false;
        s.replace(at, search.size(), value);
        at += value.size();
    }
    return true;
}

// OCIO's ResolveContextVariables repeats its replacements by recursion until the string stops
// changing, without a bound: a variable holding itself ("A: $A$A") recurses until the stack or
// the memory runs out. The same passes, in the same order (the context's variables by index
// are its EnvMap's order), bounded here; OCIO is asked only once they settle.
class Resolver {
public:
    Resolver(const OCIO::Config& config, const std::string& path)
        : m_context(config.getCurrentContext()), m_path(path) {
        for (int i = 0; i < m_context->getNumStringVars(); ++i) {
            const std::string name = m_context->getStringVarNameByIndex(i);
            m_vars.push_back({"${" + name + "}", "$" + name, "%" + name + "%", m_context->getStringVarByIndex(i)});
        }
    }

    std::string resolve(const std::string& s, const std::string& what) {
        if (!has_variables(s)) return s;
        if (const auto known = m_settled.find(s); known != m_settled.end()) return known->second;
        std::string current = s;
        for (int pass = 0; has_variables(current); ++pass) {
            m_rounds += m_vars.size();
            if (m_rounds > kMaxResolveRounds)
                throw Error(m_path, "resolving its context variables (" + std::to_string(m_vars.size()) +
                                        ") in its references takes more than " + std::to_string(kMaxResolveRounds) +
                                        " rounds: refused");
            std::string next = current;
            bool bounded = true;
            for (const Variable& v : m_vars) {
                bounded = bounded && replace_all(next, v.braced, v.value, kMaxResolvedBytes) &&
                          replace_all(next, v.plain, v.value, kMaxResolvedBytes) &&
                          replace_all(next, v.windows, v.value, kMaxResolvedBytes);
            }
            if (next == current) break;
            if (!bounded || pass + 1 >= kMaxResolvePasses)
                throw Error(m_path, "the context variables in " + what + " " + quote(s) +
                                        " do not settle (a variable refers to itself, or they grow past " +
                                        std::to_string(kMaxResolvedBytes) + " bytes): refused");
            current = std::move(next);
        }
        return m_settled[s] = m_context->resolveStringVar(s.c_str());
    }

private:
    struct Variable {
        std::string braced, plain, windows, value;  // ${NAME}, $NAME, %NAME%
    };
    OCIO::ConstContextRcPtr m_context;
    const std::string& m_path;
    std::vector<Variable> m_vars;
    std::map<std::string, std::string> m_settled;
    std::uint64_t m_rounds = 0;
};

// ---------------------------------------------------------------------------------------------
// The transform graph

enum class Kind { Space, Look, ViewTransform, Named, View };

struct Node {
    Kind kind;
    std::string name;
    std::string display;  // a View's display

    std::string key() const { return std::string(1, char('0' + int(kind))) + display + '\x1f' + name; }
    std::string label() const {
        switch (kind) {
            case Kind::Space: return "colour space " + quote(name);
            case Kind::Look: return "look " + quote(name);
            case Kind::ViewTransform: return "view transform " + quote(name);
            case Kind::Named: return "named transform " + quote(name);
            case Kind::View: return "view " + quote(name) + " of display " + quote(display);
        }
        return quote(name);
    }
};

// What a node or transform costs OCIO: the transforms and references it expands to with every
// reference followed (saturating; a reference counts even when it adds no transform: OCIO still
// builds its allocation no-ops, and 2^15 of them took its CPU processor past 20 s), and how many
// levels (nodes and groups) lie below it.
struct Cost {
    std::uint64_t steps = 0;
    int height = 0;

    void add(const Cost& c) {
        steps = std::min<std::uint64_t>(steps + c.steps, std::uint64_t(1) << 62);
        height = std::max(height, c.height);
    }
};

// OCIO's LookParseResult: looks separated by ',' or ':', options by '|', each with an optional
// '+' or '-' for its direction.
std::vector<std::string> look_names(const std::string& looks) {
    std::vector<std::string> out;
    std::string token;
    auto flush = [&] {
        const std::size_t b = token.find_first_not_of(" \t\r\n+-");
        const std::size_t e = token.find_last_not_of(" \t\r\n");
        if (b != std::string::npos && e != std::string::npos && e >= b) out.push_back(token.substr(b, e - b + 1));
        token.clear();
    };
    for (const char c : looks) {
        if (c == ',' || c == ':' || c == '|') flush();
        else token += c;
    }
    flush();
    return out;
}

// Walks nodes depth first with three states (unvisited, on the path, done) and memoised costs:
// linear in the config, whatever it holds. The edges are those OCIO's Build*Ops functions
// follow (ColorSpaceTransform.cpp, LookTransform.cpp, DisplayViewTransform.cpp), taken in both
// directions at once: a node counts both its to- and from-reference transforms, so that a cycle
// through either direction is found.
class Graph {
public:
    // `each_use`: every reference is expanded again, not taken from memory, so that files()
    // counts each use of a LUT (only once check_all has passed: expansions are then bounded).
    Graph(const OCIO::Config& config, const std::string& path, Resolver& resolver, bool each_use = false)
        : m_config(config), m_path(path), m_resolver(resolver), m_each_use(each_use) {}

    // Every node of the config, every string OCIO resolves context variables in.
    void check_all() {
        for (int i = 0; i < m_config.getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL); ++i)
            visit({Kind::Space, m_config.getColorSpaceNameByIndex(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL, i), ""}, 0);
        for (int i = 0; i < m_config.getNumLooks(); ++i) visit({Kind::Look, m_config.getLookNameByIndex(i), ""}, 0);
        for (int i = 0; i < m_config.getNumViewTransforms(); ++i)
            visit({Kind::ViewTransform, m_config.getViewTransformNameByIndex(i), ""}, 0);
        for (int i = 0; i < m_config.getNumNamedTransforms(OCIO::NAMEDTRANSFORM_ALL); ++i)
            visit({Kind::Named, m_config.getNamedTransformNameByIndex(OCIO::NAMEDTRANSFORM_ALL, i), ""}, 0);
        for (int d = 0; d < m_config.getNumDisplaysAll(); ++d) {
            const std::string display = m_config.getDisplayAll(d);
            for (OCIO::ViewType type : {OCIO::VIEW_DISPLAY_DEFINED, OCIO::VIEW_SHARED})
                for (int v = 0; v < m_config.getNumViews(type, display.c_str()); ++v)
                    visit({Kind::View, m_config.getView(type, display.c_str(), v), display}, 0);
        }
        for (int i = 0; i < m_config.getNumSearchPaths(); ++i) m_resolver.resolve(m_config.getSearchPath(i), "the search path");
    }

    void visit_space(const std::string& name) { reference(name, name, 0, nullptr); }
    void visit_view(const std::string& display, const std::string& view) { visit({Kind::View, view, display}, 0); }

    // The FileTransform sources met so far, unresolved, and how many times each was met.
    const std::map<std::string, std::uint64_t>& files() const { return m_files; }

private:
    enum class State { Fresh, OnPath, Done };
    struct Entry {
        State state = State::Fresh;
        Cost cost;
    };

    // Labels joined by " -> ", the middle of a long chain left out.
    static std::string chain_text(const std::vector<std::string>& labels) {
        std::string text;
        for (std::size_t i = 0; i < labels.size(); ++i) {
            if (i == 3 && labels.size() > 7) {
                text += " -> ...";
                i = labels.size() - 3;
            }
            text += (text.empty() ? "" : " -> ") + labels[i];
        }
        return text;
    }

    [[noreturn]] void too_deep(const std::string& last) const {
        std::vector<std::string> chain = m_path_labels;
        chain.push_back(last);
        throw Error(m_path, "its references and groups nest deeper than " + std::to_string(kMaxReferenceDepth) +
                                " levels (" + chain_text(chain) + "): refused");
    }

    Cost visit(const Node& node, int depth) {
        Entry& entry = m_entries[node.key()];  // std::map: references stay valid as it grows
        if (entry.state == State::Done && !m_each_use) {
            if (depth + entry.cost.height > kMaxReferenceDepth) too_deep(node.label());
            return entry.cost;
        }
        if (entry.state == State::OnPath) {
            const auto first = std::find(m_path_keys.begin(), m_path_keys.end(), node.key());
            std::vector<std::string> through(m_path_labels.begin() + (first - m_path_keys.begin()) + 1, m_path_labels.end());
            const bool direct = through.empty();
            through.push_back(node.label());
            throw Error(m_path, node.label() + " refers to itself" + (direct ? "" : " through " + chain_text(through)) +
                                    ": refused");
        }
        if (depth >= kMaxReferenceDepth) too_deep(node.label());
        entry.state = State::OnPath;
        m_path_keys.push_back(node.key());
        m_path_labels.push_back(node.label());
        Cost cost = expand(node, depth);
        cost.height += 1;
        cost.add({1, 0});
        if (cost.steps > kMaxExpandedTransforms)
            throw Error(m_path, node.label() + " expands to more than " + std::to_string(kMaxExpandedTransforms) +
                                    " transforms with its references followed: refused");
        m_path_keys.pop_back();
        m_path_labels.pop_back();
        Entry& done = m_entries[node.key()];
        done.state = State::Done;
        done.cost = cost;
        return cost;
    }

    // The transforms and references of one node.
    Cost expand(const Node& node, int depth) {
        Cost cost;
        switch (node.kind) {
            case Kind::Space:
                if (OCIO::ConstColorSpaceRcPtr cs = m_config.getColorSpace(node.name.c_str())) {
                    cost.add(transform(cs->getTransform(OCIO::COLORSPACE_DIR_TO_REFERENCE), depth + 1));
                    cost.add(transform(cs->getTransform(OCIO::COLORSPACE_DIR_FROM_REFERENCE), depth + 1));
                }
                break;
            case Kind::Look:
                if (OCIO::ConstLookRcPtr look = m_config.getLook(node.name.c_str())) {
                    const std::string space = look->getProcessSpace();
                    cost.add(reference(space, space, depth + 1, nullptr));
                    cost.add(transform(look->getTransform(), depth + 1));
                    cost.add(transform(look->getInverseTransform(), depth + 1));
                }
                break;
            case Kind::ViewTransform:
                if (OCIO::ConstViewTransformRcPtr vt = m_config.getViewTransform(node.name.c_str())) {
                    cost.add(transform(vt->getTransform(OCIO::VIEWTRANSFORM_DIR_TO_REFERENCE), depth + 1));
                    cost.add(transform(vt->getTransform(OCIO::VIEWTRANSFORM_DIR_FROM_REFERENCE), depth + 1));
                }
                break;
            case Kind::Named:
                if (OCIO::ConstNamedTransformRcPtr nt = m_config.getNamedTransform(node.name.c_str())) {
                    cost.add(transform(nt->getTransform(OCIO::TRANSFORM_DIR_FORWARD), depth + 1));
                    cost.add(transform(nt->getTransform(OCIO::TRANSFORM_DIR_INVERSE), depth + 1));
                }
                break;
            case Kind::View: {
                const char* display = node.display.c_str();
                const char* view = node.name.c_str();
                // BuildDisplayOps: the view transform (or a named transform in its place), the
                // colour space (the display's name for <USE_DISPLAY_NAME>), the looks, and the
                // default view transform wherever the source's reference type differs from the
                // view's, its display space's or a look's: the source is not known here, so always
                // (a view of a display space without a view transform goes through it).
                cost.add(default_view_transform(depth + 1));
                const std::string vt_name = m_config.getDisplayViewTransformName(display, view);
                if (!vt_name.empty()) {
                    if (OCIO::ConstViewTransformRcPtr vt = m_config.getViewTransform(vt_name.c_str())) {
                        cost.add(visit({Kind::ViewTransform, vt->getName(), ""}, depth + 1));
                    } else if (OCIO::ConstNamedTransformRcPtr nt = m_config.getNamedTransform(vt_name.c_str())) {
                        cost.add(visit({Kind::Named, nt->getName(), ""}, depth + 1));
                    }
                }
                std::string space = m_config.getDisplayViewColorSpaceName(display, view);
                if (space == OCIO::OCIO_VIEW_USE_DISPLAY_NAME) space = node.display;
                cost.add(reference(space, space, depth + 1, nullptr));
                cost.add(looks(m_config.getDisplayViewLooks(display, view), depth + 1, nullptr));
                break;
            }
        }
        return cost;
    }

    // A colour space or named transform by name, as BuildColorSpaceOps finds it: the colour
    // space by the resolved name (roles and aliases included), else the named transform by
    // the name as written.
    // A colour space's reference type is added to `types`.
    Cost reference(const std::string& resolved, const std::string& written, int depth,
                   std::vector<OCIO::ReferenceSpaceType>* types) {
        if (resolved.empty()) return {};
        if (OCIO::ConstColorSpaceRcPtr cs = m_config.getColorSpace(resolved.c_str())) {
            if (types) types->push_back(cs->getReferenceSpaceType());
            return visit({Kind::Space, cs->getName(), ""}, depth);
        }
        OCIO::ConstNamedTransformRcPtr nt = m_config.getNamedTransform(written.c_str());
        if (!nt) nt = m_config.getNamedTransform(resolved.c_str());
        if (nt) return visit({Kind::Named, nt->getName(), ""}, depth);
        return {};  // unknown: OCIO reports it
    }

    static bool mixed(const std::vector<OCIO::ReferenceSpaceType>& types) {
        return std::count(types.begin(), types.end(), OCIO::REFERENCE_SPACE_SCENE) != std::ptrdiff_t(types.size()) &&
               std::count(types.begin(), types.end(), OCIO::REFERENCE_SPACE_DISPLAY) != std::ptrdiff_t(types.size());
    }

    Cost default_view_transform(int depth) {
        OCIO::ConstViewTransformRcPtr vt = m_config.getDefaultSceneToDisplayViewTransform();
        return vt ? visit({Kind::ViewTransform, vt->getName(), ""}, depth) : Cost{};
    }

    // The looks of a look list; their process spaces' reference types are added to `types`.
    Cost looks(const std::string& list, int depth, std::vector<OCIO::ReferenceSpaceType>* types) {
        Cost cost;
        for (const std::string& name : look_names(list)) {
            OCIO::ConstLookRcPtr look = m_config.getLook(name.c_str());
            if (!look) continue;
            if (types)
                if (OCIO::ConstColorSpaceRcPtr cs = m_config.getColorSpace(look->getProcessSpace()))
                    types->push_back(cs->getReferenceSpaceType());
            cost.add(visit({Kind::Look, look->getName(), ""}, depth));
        }
        return cost;
    }

    Cost transform(const OCIO::ConstTransformRcPtr& t, int depth) {
        if (!t) return {};
        if (depth >= kMaxReferenceDepth) too_deep("a transform");
        Cost cost{1, 0};
        if (auto group = OCIO::DynamicPtrCast<const OCIO::GroupTransform>(t)) {
            for (int i = 0; i < group->getNumTransforms(); ++i) cost.add(transform(group->getTransform(i), depth + 1));
            cost.height += 1;
        } else if (auto cst = OCIO::DynamicPtrCast<const OCIO::ColorSpaceTransform>(t)) {
            // Between spaces of different reference types OCIO inserts the default view transform.
            const std::string src = cst->getSrc(), dst = cst->getDst();
            std::vector<OCIO::ReferenceSpaceType> types;
            cost.add(reference(m_resolver.resolve(src, "the ColorSpaceTransform source"), src, depth, &types));
            cost.add(reference(m_resolver.resolve(dst, "the ColorSpaceTransform destination"), dst, depth, &types));
            if (mixed(types)) cost.add(default_view_transform(depth));
        } else if (auto lt = OCIO::DynamicPtrCast<const OCIO::LookTransform>(t)) {
            std::vector<OCIO::ReferenceSpaceType> types;
            cost.add(reference(lt->getSrc(), lt->getSrc(), depth, &types));
            cost.add(reference(lt->getDst(), lt->getDst(), depth, &types));
            cost.add(looks(lt->getLooks(), depth, &types));
            if (mixed(types)) cost.add(default_view_transform(depth));
        } else if (auto dvt = OCIO::DynamicPtrCast<const OCIO::DisplayViewTransform>(t)) {
            cost.add(reference(dvt->getSrc(), dvt->getSrc(), depth, nullptr));
            if (*dvt->getDisplay() && *dvt->getView())
                cost.add(visit({Kind::View, dvt->getView(), dvt->getDisplay()}, depth));
        } else {
            if (auto file = OCIO::DynamicPtrCast<const OCIO::FileTransform>(t)) {
                const std::string src = file->getSrc();
                m_resolver.resolve(src, "the LUT name");
                m_resolver.resolve(file->getCCCId(), "the CCC id");
                ++m_files[src];
            }
        }
        return cost;
    }

    const OCIO::Config& m_config;
    const std::string& m_path;
    Resolver& m_resolver;
    std::map<std::string, Entry> m_entries;
    std::vector<std::string> m_path_keys, m_path_labels;
    bool m_each_use;
    std::map<std::string, std::uint64_t> m_files;
};

}  // namespace

std::string quote(const std::string& s) { return "'" + s + "'"; }

std::string join_quoted(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& s : items) out += (out.empty() ? "" : ", ") + quote(s);
    return out;
}

// OCIO's ContainsContextVariables: a '$', or two distinct '%'.
bool has_variables(const std::string& s) {
    if (s.find('$') != std::string::npos) return true;
    const std::size_t first = s.find('%');
    return first != std::string::npos && s.rfind('%') != first;
}

void check_config_text(const std::string& text, const std::string& path) {
    YAML::Node loaded;
    try {
        loaded = YAML::Load(text);
    } catch (const YAML::Exception&) {
        return;  // not YAML: OCIO says why
    }
    const YAML::Node& root = loaded;  // const: operator[] must not add keys
    try {
        YamlWalk(path).walk(root, 0);
        if (!root.IsMap()) return;
        // OCIO adds names one by one and checks each against all before it (Config::addColorSpace,
        // ColorSpaceSet, refreshActiveColorSpaces): time grows with the square of the names.
        std::size_t names = 0;
        for (const char* list : {"colorspaces", "display_colorspaces", "named_transforms"}) {
            const YAML::Node items = root[list];
            if (!is_sequence(items)) continue;
            names += items.size();
            for (const auto& item : items) {
                if (!item.IsMap()) continue;
                const YAML::Node aliases = item["aliases"];
                if (is_sequence(aliases)) names += aliases.size();
            }
        }
        if (names > kMaxConfigNames)
            throw Error(path, "it names " + std::to_string(names) +
                                  " colour spaces, named transforms and aliases, above npf's cap of " +
                                  std::to_string(kMaxConfigNames) + ": refused");
        const YAML::Node rules = root["file_rules"];
        if (is_sequence(rules)) {
            for (const auto& rule : rules) {
                if (!rule.IsMap()) continue;
                for (const char* key : {"pattern", "extension", "regex"}) {
                    const YAML::Node value = rule[key];
                    if (!value.IsDefined() || !value.IsScalar() || value.Scalar().size() <= kMaxFileRuleBytes) continue;
                    const int line = value.Mark().line;
                    throw Error(path, std::string("a file rule's ") + key + (line >= 0 ? " (line " + std::to_string(line + 1) + ")" : "") +
                                          " has " + std::to_string(value.Scalar().size()) + " characters, above npf's cap of " +
                                          std::to_string(kMaxFileRuleBytes) +
                                          " (OpenColorIO compiles it with std::regex, which recurses per character): refused");
                }
            }
        }
    } catch (const YAML::Exception& e) {
        // yaml-cpp parsed it but cannot walk it: not a config to hand on unchecked.
        throw Error(path, std::string("invalid OpenColorIO config: ") + first_line(e.what()));
    }
}

void check_config_graph(const OCIO::Config& config, const std::string& path) {
    try {
        Resolver resolver(config, path);
        Graph graph(config, path, resolver);
        graph.check_all();
    } catch (const OCIO::Exception& e) {
        throw Error(path, "invalid OpenColorIO config: " + ocio_reason(e, &config));
    }
}

void check_display_luts(const OCIO::Config& config, const std::string& path, const std::string& input,
                        const std::string& display, const std::string& view) {
    try {
        Resolver resolver(config, path);
        Graph graph(config, path, resolver, true);
        graph.visit_space(input);
        graph.visit_view(display, view);
        if (graph.files().empty()) return;
        std::vector<std::string> search_paths;
        for (int i = 0; i < config.getNumSearchPaths(); ++i)
            search_paths.push_back(resolver.resolve(config.getSearchPath(i), "the search path"));
        const std::vector<std::string> folders = search_folders(config.getWorkingDir(), search_paths);
        // OCIO builds a table for each use of a LUT (1000 uses of one 7 MB .cube took 3 GB and
        // 14 s): the bytes of all uses together are bounded as one LUT's are.
        std::uint64_t total = 0, uses = 0;
        for (const auto& [src, count] : graph.files()) {
            total += check_lut(path, src, resolver.resolve(src, "the LUT name"), folders) * count;
            uses += count;
        }
        if (total > kMaxLutBytes)
            throw Error(path, "the display transform from " + quote(input) + " to " + quote(display) + " / " + quote(view) +
                                  " reads LUT files " + std::to_string(uses) + " times, " + std::to_string(total) +
                                  " bytes in all, above npf's cap of " + std::to_string(kMaxLutBytes) + " (256 MiB): refused");
    } catch (const OCIO::Exception& e) {
        throw Error(path, "cannot check the config's LUTs: " + ocio_reason(e, &config));
    }
}

}  // namespace npf::color::detail
