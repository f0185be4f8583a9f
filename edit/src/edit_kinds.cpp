#include <npf/edit/edit_kinds.h>

#include <npf/core/error.h>
#include <npf/core/number_text.h>

namespace npf::edit {

namespace kinds {
// Each in edit/src/kinds/, in the order of the list below.
EditKind matrix();
EditKind stretch();
EditKind rotate();
EditKind roughness();
EditKind sharpen();
EditKind blur();
EditKind diffuse();
EditKind specular();
EditKind thin_film();
EditKind compress();
EditKind limit_albedo();
}  // namespace kinds

const EditKinds& edit_kinds() {
    // The order is that of the recipe's messages ("expected one of: matrix, ...") and of the help.
    static const EditKinds all = {
        kinds::matrix(),   kinds::stretch(),  kinds::rotate(),    kinds::roughness(),
        kinds::sharpen(),  kinds::blur(),     kinds::diffuse(),   kinds::specular(),
        kinds::thin_film(), kinds::compress(), kinds::limit_albedo(),
    };
    return all;
}

const EditKind* find_edit_kind(const EditKinds& kinds, const std::string& key) {
    for (const EditKind& k : kinds) {
        if (k.key == key) return &k;
    }
    return nullptr;
}

const EditKind* find_edit_kind_of_flag(const EditKinds& kinds, const std::string& flag) {
    for (const EditKind& k : kinds) {
        for (const EditFlag& f : k.flags) {
            if (f.name == flag) return &k;
        }
    }
    return nullptr;
}

std::string edit_kind_keys(const EditKinds& kinds, const std::string& last_separator) {
    std::string keys;
    for (std::size_t i = 0; i < kinds.size(); ++i) {
        if (i > 0) keys += i + 1 == kinds.size() ? last_separator : ", ";
        keys += kinds[i].key;
    }
    return keys;
}

void check_edit_settings(const EditKinds& kinds, const GivenFlags& given) {
    for (const EditKind& k : kinds) {
        if (k.check_settings) k.check_settings(given);
    }
    for (const EditKind& k : kinds) {
        const EditFlag* first_step = nullptr;
        bool step_given = false;
        for (const EditFlag& f : k.flags) {
            if (!f.makes_step) continue;
            if (!first_step) first_step = &f;
            step_given = step_given || given.count(f.name) > 0;
        }
        if (step_given || !first_step) continue;
        for (const EditFlag& f : k.flags) {
            if (!f.makes_step && given.count(f.name)) throw Error(f.name, "applies to " + first_step->name + ", which is not given");
        }
    }
}

std::optional<EditStep> edit_step_from_flag(const EditKinds& kinds, const std::string& flag, const std::string& text,
                                             const GivenFlags& given) {
    const EditKind* kind = find_edit_kind_of_flag(kinds, flag);
    if (!kind) return std::nullopt;
    for (const EditFlag& f : kind->flags) {
        if (f.name == flag && !f.makes_step) return std::nullopt;
    }
    EditStep s = kind->from_flag(flag, text, given);
    s.origin = flag;
    return s;
}

double flag_number(const std::string& flag, const std::string& text) { return parse_finite_number(text, flag); }

double flag_positive(const std::string& flag, const std::string& text) {
    const double d = flag_number(flag, text);
    if (!(d > 0.0)) throw Error(flag, "must be positive, got '" + text + "'");
    return d;
}

std::vector<double> flag_numbers(const std::string& flag, const std::string& text, std::size_t count) {
    std::vector<double> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        out.push_back(flag_number(flag, text.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (out.size() != count) {
        throw Error(flag, "expects " + std::to_string(count) + " comma-separated numbers, got '" + text + "'");
    }
    return out;
}

}  // namespace npf::edit
