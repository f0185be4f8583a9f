#include <npf/core/brdf.h>

#include <npf/core/error.h>

#include <cmath>
#include <cstdio>

namespace npf {

void check_value_bound(const std::string& source, double bound, const std::string& terms) {
    if (std::isfinite(bound) && bound <= kMaxMaterialValue) return;
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", bound);
    throw Error(source, "its tables can give f_r cos(theta_i) cos(theta_o) up to " + std::string(std::isfinite(bound) ? text : "infinity") +
                            " 1/sr (" + terms + "), above the 1e12 a material may reach: refused as corrupt");
}

bool Brdf::albedo_by_quadrature(const Vec3&, const ChannelQuery&, std::vector<double>&) const { return false; }

ChannelQuery Brdf::query(const Channels& requested) const {
    const BrdfInfo& i = info();
    return make_channel_query(i.channels, requested, i.path.empty() ? i.format : i.path);
}

}  // namespace npf
