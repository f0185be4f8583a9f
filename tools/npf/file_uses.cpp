#include "file_uses.h"

#include <npf/materials/yaml_context.h>
#include <npf/core/text.h>

namespace npf::cli {

FileUses& FileUses::input(const std::string& path, const std::string& role) {
    m_uses.push_back({path, role, false});
    const std::string ext = lowercase(path.size() > 5 ? path.substr(path.size() - 5) : path);
    if (ends_with(ext, ".yaml") || ends_with(ext, ".yml")) {
        for (const auto& [name, resolved] : files_named_in_yaml(path)) m_uses.push_back({resolved, role + "'s " + name, false});
    }
    return *this;
}

FileUses& FileUses::output(const std::string& path, const std::string& role) {
    m_uses.push_back({path, role, true});
    return *this;
}

}  // namespace npf::cli
