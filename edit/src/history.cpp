#include "history.h"

#include <npf/edit/recipe.h>

#include <algorithm>
#include <cstdio>
#include <utility>
#include <vector>

namespace npf::edit {

namespace {

bool is_history_key(const std::string& key, int* number) {
    if (key.size() < 6 || key.compare(0, 5, "edit_") != 0) return false;
    int n = 0;
    for (std::size_t i = 5; i < key.size(); ++i) {
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
    std::snprintf(b, sizeof b, "edit_%03d", number);
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
