#include <npf/core/brdf.h>

namespace npf {

ChannelQuery Brdf::query(const Channels& requested) const {
    const BrdfInfo& i = info();
    return make_channel_query(i.channels, requested, i.path.empty() ? i.format : i.path);
}

}  // namespace npf
