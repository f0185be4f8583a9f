// matrix: the NDF transformed by any 3x3 matrix acting on the normals (ndf_transform.h).
#include "recipe_values.h"

#include <npf/edit/edit_kinds.h>

namespace npf::edit::kinds {

namespace {

// Nine numbers (row-major) or three rows of three.
Mat3 recipe_matrix(const YamlContext& cx, const YAML::Node& node) {
    Mat3 m;
    const char* key = "matrix";
    if (!node.IsSequence()) cx.fail(node, key, "expected [[a, b, c], [d, e, f], [g, h, i]]");
    if (node.size() == 9) {
        for (std::size_t i = 0; i < 9; ++i) m.m[i] = cx.number(node[i], key);
        return m;
    }
    if (node.size() != 3) cx.fail(node, key, "expected three rows of three numbers (or nine numbers)");
    for (std::size_t i = 0; i < 3; ++i) {
        if (!node[i].IsSequence() || node[i].size() != 3) cx.fail(node[i], key, "each row holds three numbers");
        for (std::size_t j = 0; j < 3; ++j) m(int(i), int(j)) = cx.number(node[i][j], key);
    }
    return m;
}

}  // namespace

EditKind matrix() {
    return make_edit_kind<Mat3>({
        "matrix",
        {{"--matrix", "NDF transform by the 3x3 matrix a,b,c,d,e,f,g,h,i (row-major, acts on normals)"}},
        recipe_matrix,
        [](const std::string& flag, const std::string& text, const GivenFlags&) {
            const std::vector<double> v = flag_numbers(flag, text, 9);
            Mat3 m;
            for (std::size_t i = 0; i < 9; ++i) m.m[i] = v[i];
            return m;
        },
        [](const Mat3& m) { return EditStep::ndf(m, "matrix " + matrix_text(m)); },
    });
}

}  // namespace npf::edit::kinds
