#include <npf/core/error.h>

#include <utility>

namespace npf {

namespace {
std::string compose(const std::string& source, const std::string& problem) {
    return source.empty() ? problem : source + ": " + problem;
}
}  // namespace

Error::Error(std::string source, const std::string& problem)
    : std::runtime_error(compose(source, problem)), m_source(std::move(source)), m_problem(problem) {}

}  // namespace npf
