// The edit kinds: every step that edit recipes and the flags of `npf edit` know (docs/editing.md),
// one file each in edit/src/kinds/. A kind names its recipe key and its flags (with their help),
// reads its typed parameters from a recipe's value or from a flag's text, and builds its step,
// label included, from those parameters alone. The recipe reader (recipe.h) and `npf edit` build
// steps only through this list, and the help of `npf edit` lists its flags: a new kind is a new
// file in edit/src/kinds/, declared and listed in edit/src/edit_kinds.cpp. Its step carries its
// own operation (EditStep::operation), so apply_edits needs no change for it.
#pragma once

#include <npf/edit/edit_step.h>

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace YAML {
class Node;
}

namespace npf {
struct YamlContext;
}

namespace npf::edit {

struct EditFlag {
    std::string name;  // "--stretch-tangent"
    std::string help;  // its line in `npf edit --help`
    bool takes_value = true;
    // A step of its own, or a setting of the kind's steps (--film-base for --thin-film), which is
    // an error without a step flag of its kind.
    bool makes_step = true;
};

// The flags of a command line, each with its last value ("" for a switch).
using GivenFlags = std::map<std::string, std::string>;

struct EditKind {
    std::string key;              // the recipe's step key ("stretch")
    std::vector<EditFlag> flags;  // in the order `npf edit --help` lists them
    // The step of a recipe's `key: value`; errors name the recipe line through `cx`.
    std::function<EditStep(const YamlContext& cx, const YAML::Node& value)> from_recipe;
    // The step of one of the kind's step flags and its text; `given` holds the settings.
    std::function<EditStep(const std::string& flag, const std::string& text, const GivenFlags& given)> from_flag;
    // Optional: checks the values of the kind's setting flags once, before any step is built.
    std::function<void(const GivenFlags& given)> check_settings;
};

// A kind by its typed parameters: the recipe and the flags each read a Params, and build() alone
// makes the step and its label from it, so that the two cannot build different steps.
template <typename Params>
struct EditKindDefinition {
    std::string key;
    std::vector<EditFlag> flags;
    std::function<Params(const YamlContext& cx, const YAML::Node& value)> read_recipe;
    std::function<Params(const std::string& flag, const std::string& text, const GivenFlags& given)> read_flag;
    std::function<EditStep(const Params&)> build;
    std::function<void(const GivenFlags& given)> check_settings = {};
};

template <typename Params>
EditKind make_edit_kind(EditKindDefinition<Params> d) {
    EditKind kind;
    kind.key = std::move(d.key);
    kind.flags = std::move(d.flags);
    kind.from_recipe = [read = std::move(d.read_recipe), build = d.build](const YamlContext& cx, const YAML::Node& value) {
        return build(read(cx, value));
    };
    kind.from_flag = [read = std::move(d.read_flag), build = d.build](const std::string& flag, const std::string& text,
                                                                      const GivenFlags& given) {
        return build(read(flag, text, given));
    };
    kind.check_settings = std::move(d.check_settings);
    return kind;
}

using EditKinds = std::vector<EditKind>;

// The kinds of this library, in the order that the recipe's messages and the help list them.
const EditKinds& edit_kinds();

// nullptr when there is none.
const EditKind* find_edit_kind(const EditKinds& kinds, const std::string& key);
const EditKind* find_edit_kind_of_flag(const EditKinds& kinds, const std::string& flag);

// The keys, "matrix, stretch, ..., compress" + last_separator + "limit_albedo".
std::string edit_kind_keys(const EditKinds& kinds, const std::string& last_separator);

// Command line, before any step: the values of every kind's setting flags, then that each setting
// given comes with a step flag of its kind. Throws npf::Error naming the flag.
void check_edit_settings(const EditKinds& kinds, const GivenFlags& given);
// The step of `flag` (origin: the flag), nothing when it is not a step flag. Throws npf::Error
// naming the flag for a bad value.
std::optional<EditStep> edit_step_from_flag(const EditKinds& kinds, const std::string& flag, const std::string& text,
                                             const GivenFlags& given);

// Flag values as numbers (finite); errors name the flag and quote the text.
double flag_number(const std::string& flag, const std::string& text);
double flag_positive(const std::string& flag, const std::string& text);
// `count` comma-separated numbers ("0.5,0.2,0.1").
std::vector<double> flag_numbers(const std::string& flag, const std::string& text, std::size_t count);

}  // namespace npf::edit
