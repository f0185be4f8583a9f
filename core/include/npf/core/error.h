// npf::Error: the one exception type for user-facing errors (bad files, bad flags, bad
// configuration). It always names the file (or other source) and the problem, so that a
// tool can print what() and exit without further decoration.
//
// The shading hot path does not throw; loaders, converters and tools do.
#pragma once

#include <stdexcept>
#include <string>

namespace npf {

class Error : public std::runtime_error {
public:
    // `source` is usually a file path; it may be empty when there is no file involved.
    Error(std::string source, const std::string& problem);

    const std::string& source() const noexcept { return m_source; }
    const std::string& problem() const noexcept { return m_problem; }

private:
    std::string m_source;
    std::string m_problem;
};

}  // namespace npf
