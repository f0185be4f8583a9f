#include <npf/render/render_settings.h>

#include <npf/core/number_text.h>

namespace npf::render {

std::uint64_t WholeRenderSetting::parse(const std::string& text, const std::string& what) const {
    return parse_whole_number(text, min, max, what);
}

std::pair<std::size_t, std::size_t> parse_image_size(const std::string& text, const std::string& what) {
    const std::size_t x = text.find('x');
    if (x == std::string::npos) {
        const std::size_t side = std::size_t(kSideSetting.parse(text, what));
        return {side, side};
    }
    return {std::size_t(kSideSetting.parse(text.substr(0, x), what)), std::size_t(kSideSetting.parse(text.substr(x + 1), what))};
}

}  // namespace npf::render
