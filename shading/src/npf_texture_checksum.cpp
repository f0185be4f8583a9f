// npf:tables_checksum (npf_texture_parts.h), written by the writer and checked by the reader.
#include "npf_texture_parts.h"

#include <cstdint>
#include <cstdio>
#include <cstring>

namespace npf {

std::string tables_checksum(const NpfModel& m) {
    std::uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a 64: offset basis and prime
    const auto add = [&hash](float value) {
        std::uint32_t bits;
        std::memcpy(&bits, &value, sizeof bits);
        for (int byte = 0; byte < 4; ++byte) {
            hash ^= (bits >> (8 * byte)) & 0xffu;
            hash *= 0x100000001b3ull;
        }
    };
    const auto add_all = [&add](const std::vector<float>& values) {
        for (float v : values) add(v);
    };
    const std::size_t C = m.channel_count();
    const auto add_weights = [&](const SpectralBasis& s) {  // channel k of the spectral part: weight k of every c
        const std::size_t rank = std::size_t(s.rank);
        for (std::size_t k = 0; k < rank; ++k)
            for (std::size_t c = 0; c < C; ++c) add(s.weights[c * rank + k]);
    };
    add_all(m.D.basis);
    add_all(m.G.basis);
    add_all(m.F);
    for (std::size_t c = 0; c < C; ++c) add(m.channels.is_rgb() ? float(c) : m.channels.wavelengths()[c]);
    add_all(m.rho_d);
    add_all(m.rho_s);
    add_weights(m.D);
    add_weights(m.G);
    add_weights(m.detail);
    add_all(m.detail.basis);
    char text[32];
    std::snprintf(text, sizeof text, "fnv1a64:%016llx", static_cast<unsigned long long>(hash));
    return text;
}

}  // namespace npf
