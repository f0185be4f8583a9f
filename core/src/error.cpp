#include <npf/core/error.h>

#include <npf/core/text.h>

#include <utility>

namespace npf {

namespace {
// One line always (error.h): control characters in a file name or a quoted value are escaped.
std::string compose(const std::string& source, const std::string& problem) {
    return printable(source.empty() ? problem : source + ": " + problem);
}
}  // namespace

Error::Error(std::string source, const std::string& problem)
    : std::runtime_error(compose(source, problem)), m_source(std::move(source)), m_problem(problem) {}

}  // namespace npf
