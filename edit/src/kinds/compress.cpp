// compress: D and G re-compressed across wavelengths to given ranks or PCA ratios (compression.h).
#include "recipe_values.h"

#include "../tables.h"

#include <npf/core/number_text.h>
#include <npf/core/error.h>
#include <npf/edit/edit_kinds.h>

#include <cmath>

namespace npf::edit::kinds {

namespace {

struct Recompression {
    bool by_rank = true;  // else by PCA ratio
    double d = 1.0, g = 1.0;
    std::string named;  // the two values as the label names them: a flag's text, the recipe's numbers
};

// What is wrong with the values, "" when nothing.
std::string problem(const Recompression& r) {
    if (r.by_rank) {
        const bool whole = r.d >= 1.0 && r.g >= 1.0 && r.d == std::floor(r.d) && r.g == std::floor(r.g);
        return whole ? "" : "ranks are whole numbers >= 1";
    }
    return r.d > 0.0 && r.d <= 1.0 && r.g > 0.0 && r.g <= 1.0 ? "" : "ratios are in (0, 1]";
}

Recompression read_recipe(const YamlContext& cx, const YAML::Node& v) {
    cx.only(v, "compress", {"rank", "pca"});
    if (bool(v["rank"]) == bool(v["pca"])) cx.fail(v, "compress", "give exactly one of rank: [D, G] or pca: [D, G]");
    Recompression r;
    r.by_rank = bool(v["rank"]);
    const YAML::Node pair = r.by_rank ? v["rank"] : v["pca"];
    const char* key = r.by_rank ? "rank" : "pca";
    if (!pair.IsSequence() || pair.size() != 2) cx.fail(pair, key, "expected two values: [D, G]");
    r.d = cx.number(pair[0], key);
    r.g = cx.number(pair[1], key);
    const std::string wrong = problem(r);
    if (!wrong.empty()) cx.fail(pair, key, wrong);
    r.named = number_text(r.d) + ", " + number_text(r.g);
    return r;
}

Recompression read_flag(const std::string& flag, const std::string& text, const GivenFlags&) {
    const std::vector<double> v = flag_numbers(flag, text, 2);
    const Recompression r{flag == "--compress-rank", v[0], v[1], text};
    const std::string wrong = problem(r);
    if (!wrong.empty()) throw Error(flag, wrong);
    return r;
}

EditStep build(const Recompression& r) {
    CompressionOptions o;
    if (r.by_rank) {
        o.d_rank = int(r.d);
        o.g_rank = int(r.g);
    } else {
        o.d_ratio = r.d;
        o.g_ratio = r.g;
    }
    return EditStep::compress(o, std::string("compress D, G to ") + (r.by_rank ? "ranks " : "PCA ratios ") + r.named);
}

}  // namespace

EditKind compress() {
    return make_edit_kind<Recompression>({
        "compress",
        {{"--compress-rank", "re-compress D and G across wavelengths to ranks D,G (no refit; from a lossless file as convert --rank)"},
         {"--compress-pca", "re-compress D and G to the smallest ranks keeping PCA ratios D,G (e.g. 0.99,0.95)"}},
        read_recipe,
        read_flag,
        build,
    });
}

}  // namespace npf::edit::kinds
