// The render settings people give in text, each declared once with its bounds: `npf render`'s
// flags (--size, --spp, --seed, --threads) and a batch's render.* keys read them through these
// declarations, so that their ranges and parsing cannot diverge (the renderer's own bounds are
// RenderOptions::kMaxSide and kMaxSpp; render() refuses others).
#pragma once

#include <npf/render/path_tracer.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

namespace npf::render {

// A whole-number setting in [min, max].
struct WholeRenderSetting {
    const char* name;  // as the batch's key after "render." and `npf render`'s flag after "--"
    std::uint64_t min, max;
    // `text` as a whole number in [min, max] (npf::parse_whole_number: digits only); throws
    // npf::Error naming `what` otherwise.
    std::uint64_t parse(const std::string& text, const std::string& what) const;
};

inline constexpr WholeRenderSetting kSideSetting{"size", 1, RenderOptions::kMaxSide};  // pixels, each side
inline constexpr WholeRenderSetting kSppSetting{"spp", 1, RenderOptions::kMaxSpp};
inline constexpr WholeRenderSetting kSeedSetting{"seed", 0, ~std::uint64_t(0)};
inline constexpr WholeRenderSetting kThreadsSetting{"threads", 1, 1024};

// An image size: "N" (square) or "WxH", each side through kSideSetting. Returns (width, height).
std::pair<std::size_t, std::size_t> parse_image_size(const std::string& text, const std::string& what);

}  // namespace npf::render
