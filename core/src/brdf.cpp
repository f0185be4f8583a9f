#include <npf/core/brdf.h>

namespace npf {

bool Brdf::albedo_by_quadrature(const Vec3&, const ChannelQuery&, std::vector<double>&) const { return false; }

ChannelQuery Brdf::query(const Channels& requested) const {
    const BrdfInfo& i = info();
    return make_channel_query(i.channels, requested, i.path.empty() ? i.format : i.path);
}

}  // namespace npf
