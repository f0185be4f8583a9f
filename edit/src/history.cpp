#include "history.h"

#include <npf/edit/recipe.h>
#include <npf/shading/npf_texture_layout.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <utility>
#include <vector>

namespace npf::edit {

namespace {

bool is_history_key(const std::string& key, int* number) {
    const std::size_t prefix = std::strlen(npf_exr::kMetaEditPrefix);
    if (key.size() <= prefix || key.compare(0, prefix, npf_exr::kMetaEditPrefix) != 0) return false;
    int n = 0;
    for (std::size_t i = prefix; i < key.size(); ++i) {
        if (key[i] < '0' || key[i] > '9' || n > 100000000) return false;
        n = n * 10 + (key[i] - '0');
    }
    if (number) *number = n;
    return true;
}

}  // namespace

namespace detail {

int next_history_number(const NpfModel& model) {
    int next = 1;
    for (const auto& kv : model.metadata) {
        int n = 0;
        if (is_history_key(kv.first, &n)) next = std::max(next, n + 1);
    }
    return next;
}

std::string history_key(int number) {
    char b[32];
    std::snprintf(b, sizeof b, "%s%03d", npf_exr::kMetaEditPrefix, number);
    return b;
}

}  // namespace detail

std::vector<std::pair<std::string, std::string>> edit_history(const NpfModel& model) {
    std::vector<std::pair<int, std::pair<std::string, std::string>>> found;
    for (const auto& kv : model.metadata) {
        int n = 0;
        if (is_history_key(kv.first, &n)) found.push_back({n, kv});
    }
    std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::pair<std::string, std::string>> out;
    for (auto& f : found) out.push_back(std::move(f.second));
    return out;
}

}  // namespace npf::edit
