// A batch setting's value checked as it is read (private to npf_batch): the configuration's
// reader and resolve_* read values through the same checks, so that what parses resolves.
#pragma once

#include <string>
#include <vector>

namespace npf::batch::detail {

// Throws npf::Error(origin, "key 'KEY': PROBLEM").
[[noreturn]] void bad(const std::string& origin, const std::string& key, const std::string& problem);

// "true" or "false".
bool boolean(const std::string& origin, const std::string& key, const std::string& v);

// Checks a value of setting `setting` as resolve_convert_settings and resolve_render_check will
// read it; errors call it `key` (the name as written: "defaults.preset").
void check_value(const std::string& origin, const std::string& key, const std::string& setting, const std::string& v);

// The keys of a `render:` mapping (render.KEY settings).
const std::vector<std::string>& render_keys();

}  // namespace npf::batch::detail
