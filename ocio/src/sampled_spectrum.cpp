// SampledSpectrum and the two-column spectrum files (.spd).
#include <npf/core/number_text.h>
#include <npf/color/spectrum.h>
#include <npf/core/error.h>
#include <npf/core/input_file.h>
#include <npf/core/text_input.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <utility>

namespace npf::color {

namespace {

std::string number_text(double v) { return npf::number_text(v, 9); }

// Parses one whole token as a double; false for anything else ("1.5nm", "abc"). Overflow
// gives inf and "nan" gives NaN, which the caller rejects with its own message.
bool parse_double(const std::string& token, double& value) {
    const char* begin = token.c_str();
    char* end = nullptr;
    value = std::strtod(begin, &end);
    return end != begin && *end == '\0';
}

}  // namespace

SampledSpectrum::SampledSpectrum(std::vector<double> wavelengths_nm, std::vector<double> values)
    : m_wavelengths(std::move(wavelengths_nm)), m_values(std::move(values)) {
    if (m_wavelengths.size() != m_values.size())
        throw Error("spectrum", std::to_string(m_wavelengths.size()) + " wavelengths but " +
                                    std::to_string(m_values.size()) + " values");
    if (m_values.empty()) throw Error("spectrum", "no samples");
    for (std::size_t i = 0; i < m_values.size(); ++i) {
        if (!std::isfinite(m_wavelengths[i]) || !std::isfinite(m_values[i]))
            throw Error("spectrum", "non-finite wavelength or value at sample " + std::to_string(i));
        // Strictly ascending: a repeated wavelength would make the value there ambiguous.
        if (i > 0 && !(m_wavelengths[i] > m_wavelengths[i - 1]))
            throw Error("spectrum", "wavelengths not strictly ascending at sample " + std::to_string(i) +
                                        " (" + number_text(m_wavelengths[i]) + " nm after " +
                                        number_text(m_wavelengths[i - 1]) + " nm)");
    }
}

SampledSpectrum SampledSpectrum::constant(double value) {
    // One sample is constant everywhere; its wavelength is arbitrary.
    return SampledSpectrum({560.0}, {value});
}

double SampledSpectrum::operator()(double lambda_nm) const {
    if (m_values.empty()) return 0.0;
    if (!(lambda_nm > m_wavelengths.front())) return m_values.front();  // also NaN
    if (lambda_nm >= m_wavelengths.back()) return m_values.back();
    const auto hi = std::upper_bound(m_wavelengths.begin(), m_wavelengths.end(), lambda_nm);
    const std::size_t i1 = static_cast<std::size_t>(hi - m_wavelengths.begin());
    const std::size_t i0 = i1 - 1;
    const double t = (lambda_nm - m_wavelengths[i0]) / (m_wavelengths[i1] - m_wavelengths[i0]);
    return (1.0 - t) * m_values[i0] + t * m_values[i1];
}

std::vector<double> SampledSpectrum::sample(const std::vector<float>& wavelengths_nm) const {
    std::vector<double> out(wavelengths_nm.size());
    for (std::size_t i = 0; i < wavelengths_nm.size(); ++i) out[i] = (*this)(wavelengths_nm[i]);
    return out;
}

SampledSpectrum read_spd(const std::string& path) {
    LineReader in(path, "a spectrum file", kTableTextBounds);
    std::vector<double> wavelengths, values;
    std::string line;
    std::size_t line_number = 0;
    while (in.next(line)) {
        line_number = in.line_number();
        const std::string where = "line " + std::to_string(line_number) + ": ";
        const std::size_t hash = line.find('#');
        if (hash != std::string::npos) line.erase(hash);
        std::istringstream fields(line);  // splits on blanks, tabs and a trailing '\r'
        std::vector<std::string> tokens;
        for (std::string token; fields >> token;) tokens.push_back(token);
        if (tokens.empty()) continue;
        if (tokens.size() != 2)
            throw Error(path, where + "expected 2 numbers (wavelength in nm, value), found " +
                                  std::to_string(tokens.size()) + " fields");
        double row[2];
        for (int c = 0; c < 2; ++c) {
            if (!parse_double(tokens[c], row[c]))
                throw Error(path, where + "not a number: '" + tokens[c] + "'");
            if (!std::isfinite(row[c]))
                throw Error(path, where + "non-finite " + (c == 0 ? "wavelength" : "value") + " '" +
                                      tokens[c] + "'");
        }
        if (!wavelengths.empty() && !(row[0] > wavelengths.back()))
            throw Error(path, where + "wavelengths must be strictly ascending (" + number_text(row[0]) +
                                  " nm after " + number_text(wavelengths.back()) + " nm)");
        wavelengths.push_back(row[0]);
        values.push_back(row[1]);
    }
    if (values.empty()) throw Error(path, "no data rows (expected lines 'wavelength value')");
    return SampledSpectrum(std::move(wavelengths), std::move(values));
}

}  // namespace npf::color
