#include <npf/core/channels.h>
#include <npf/core/error.h>
#include <npf/core/number_text.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace npf {

Channels Channels::rgb() { return Channels(); }

Channels Channels::spectral(std::vector<float> wavelengths_nm) {
    Channels c;
    c.m_kind = ChannelKind::Spectral;
    c.m_wavelengths = std::move(wavelengths_nm);
    return c;
}

std::string Channels::describe() const {
    if (is_rgb()) return "R G B";
    std::ostringstream os;
    os.precision(7);
    for (std::size_t i = 0; i < m_wavelengths.size(); ++i) os << (i ? " " : "") << m_wavelengths[i];
    return os.str();
}

std::string Channels::name(std::size_t c) const {
    if (is_rgb()) return std::string(1, "RGB"[std::min<std::size_t>(c, 2)]);
    char b[32];
    std::snprintf(b, sizeof b, "%gnm", double(m_wavelengths.at(c)));
    return b;
}

void locate_wavelength(const float* grid, std::size_t n, float lambda, std::uint32_t& i0, std::uint32_t& i1,
                       float& t) {
    i0 = i1 = 0;
    t = 0.f;
    if (n < 2) return;
    const float* it = std::upper_bound(grid, grid + n, lambda);
    std::size_t i = it == grid ? 0 : std::size_t(it - grid) - 1;
    blend_wavelengths_at(grid, std::min(i, n - 2), lambda, i0, i1, t);
}

WavelengthLocator::WavelengthLocator(std::vector<float> ascending_grid) : m_grid(std::move(ascending_grid)) {
    const std::size_t n = m_grid.size();
    if (n < 2 || !(m_grid.back() > m_grid.front()) || !std::isfinite(m_grid.back() - m_grid.front())) return;
    m_lo = m_grid.front();
    m_hi = m_grid.back();
    const std::size_t buckets = 4 * n;
    m_buckets_per_nm = float(double(buckets) / (double(m_hi) - double(m_lo)));
    m_start.resize(buckets);
    for (std::size_t b = 0; b < buckets; ++b) {
        const float edge = float(double(m_lo) + double(b) / double(m_buckets_per_nm));
        const auto it = std::upper_bound(m_grid.begin(), m_grid.end(), edge);
        m_start[b] = std::uint32_t(it == m_grid.begin() ? 0 : std::size_t(it - m_grid.begin()) - 1);
    }
}

ChannelQuery make_channel_query(const Channels& stored, const Channels& requested,
                                const std::string& source) {
    ChannelQuery q;
    q.requested = requested;
    if (stored.is_rgb() != requested.is_rgb()) {
        throw Error(source, stored.is_rgb()
                                ? "holds RGB data; wavelengths cannot be requested from it"
                                : "holds spectral data; request wavelengths, not RGB");
    }
    if (requested.is_rgb()) {
        q.index0 = {0, 1, 2};
        q.index1 = {0, 1, 2};
        q.weight1 = {0.f, 0.f, 0.f};
        return q;
    }
    const std::vector<float>& grid = stored.wavelengths();
    if (grid.empty()) throw Error(source, "stores no wavelengths");
    if (requested.wavelengths().empty()) throw Error(source, "no wavelengths requested");
    for (float lambda : requested.wavelengths()) {
        if (!std::isfinite(lambda) || lambda <= 0.f) {
            throw Error(source, "requested wavelength " + std::to_string(lambda) +
                                    " nm is not a positive finite number");
        }
        std::uint32_t i0 = 0, i1 = 0;
        float t = 0.f;
        locate_wavelength(grid.data(), grid.size(), lambda, i0, i1, t);
        q.index0.push_back(i0);
        q.index1.push_back(i1);
        q.weight1.push_back(t);
    }
    return q;
}

std::vector<float> parse_wavelength_list(const std::string& text, const std::string& what) {
    auto number = [&](const std::string& s) {
        const std::optional<double> v = finite_number_of(s);
        if (!v || *v <= 0.0) throw Error(what, "'" + s + "' in wavelength list '" + text + "' is not a positive number (nm)");
        return *v;
    };
    std::vector<float> out;
    if (text.empty()) throw Error(what, "empty wavelength list");
    if (text.find(':') != std::string::npos) {
        std::vector<std::string> parts;
        std::stringstream ss(text);
        for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
        if (parts.size() != 3) {
            throw Error(what, "wavelength range '" + text + "' must be start:end:count");
        }
        double a = number(parts[0]), b = number(parts[1]), n = number(parts[2]);
        if (n != std::floor(n) || n > 100000) {
            throw Error(what, "count '" + parts[2] + "' in '" + text + "' must be a whole number up to 100000");
        }
        if (b < a) throw Error(what, "wavelength range '" + text + "' ends before it starts");
        std::size_t count = std::size_t(n);
        if (count == 1 && a != b) {
            throw Error(what, "a range of one wavelength needs start == end in '" + text + "'");
        }
        for (std::size_t i = 0; i < count; ++i) {
            out.push_back(float(count == 1 ? a : a + (b - a) * double(i) / double(count - 1)));
        }
        return out;
    }
    std::size_t begin = 0;
    while (true) {  // every comma separates two numbers: "450,", ",450" and "" are errors
        const std::size_t comma = text.find(',', begin);
        out.push_back(float(number(text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin))));
        if (comma == std::string::npos) break;
        begin = comma + 1;
    }
    return out;
}

Channels parse_channel_list(const std::string& text, const std::string& what) {
    if (text == "rgb") return Channels::rgb();
    try {
        return Channels::spectral(parse_wavelength_list(text, what));
    } catch (const Error& e) {
        throw Error(what, e.problem() + " (a channel list is rgb, a,b,c or start:end:count, in nm)");
    }
}

}  // namespace npf
