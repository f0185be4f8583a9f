#include <npf/render/render_channels.h>

#include <npf/color/spectrum.h>
#include <npf/color/wavelength_sampling.h>
#include <npf/core/error.h>

#include <cmath>

namespace npf::render {

namespace {

constexpr std::size_t kMinStoredNodes = 16;

}  // namespace

std::vector<float> default_render_wavelengths(const Channels& stored) {
    const std::vector<float>& wl = stored.wavelengths();
    const float lo = float(color::kVisibleMinNm), hi = float(color::kVisibleMaxNm);
    std::size_t inside = 0;
    bool ascending = true;
    for (std::size_t i = 0; i < wl.size(); ++i) {
        if (wl[i] >= lo && wl[i] <= hi) ++inside;
        if (i > 0 && !(wl[i] > wl[i - 1])) ascending = false;
    }
    // As stored: the cheapest query for every source (no interpolation; analytic materials
    // use their precomputed tables for exactly their own list). Nodes beyond 360..830 nm get
    // zero weight and are not looked up in the environment.
    if (ascending && inside >= kMinStoredNodes) return wl;
    std::vector<float> grid;
    for (int i = 0; i <= 94; ++i) grid.push_back(360.f + 5.f * float(i));
    return grid;
}

RenderChannels choose_render_channels(const BrdfInfo& material, const std::optional<Channels>& requested,
                                      const std::string& what) {
    RenderChannels rc;
    if (requested) {
        rc.channels = *requested;
    } else if (material.channels.is_rgb()) {
        rc.channels = Channels::rgb();
    } else {
        rc.channels = Channels::spectral(default_render_wavelengths(material.channels));
    }
    if (rc.channels.is_rgb()) return rc;

    const std::vector<float>& wl = rc.channels.wavelengths();
    if (wl.empty()) throw Error(what, "no wavelengths");
    bool visible = false;
    for (std::size_t i = 0; i < wl.size(); ++i) {
        if (!std::isfinite(wl[i]) || wl[i] <= 0.f) throw Error(what, "wavelengths must be positive finite numbers");
        if (i > 0 && wl[i] < wl[i - 1]) throw Error(what, "wavelengths must be in ascending order");
        if (wl[i] >= color::kVisibleMinNm && wl[i] <= color::kVisibleMaxNm) visible = true;
    }
    if (!visible) throw Error(what, "no wavelength within 360..830 nm, where the CIE observer sees");
    rc.to_rgb = color::linear_srgb_weights(wl);
    return rc;
}

}  // namespace npf::render
