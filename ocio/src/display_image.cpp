// read_scene_image and write_display_png: OpenImageIO on either side of a DisplayTransform.
#include <npf/color/display_image.h>
#include <npf/color/image_file.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/core/openexr_header.h>
#include <npf/core/text.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>

namespace npf::color {

namespace {

std::uint8_t to_8bit(float v) {
    if (!(v > 0.0f)) return 0;  // also NaN
    if (v >= 1.0f) return 255;
    return static_cast<std::uint8_t>(std::lround(v * 255.0f));
}

}  // namespace

FloatImage read_scene_image(const std::string& path) {
    std::unique_ptr<OIIO::ImageInput> in = open_image_file(path, "an image");
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.nchannels < 3)
        throw Error(path, "has " + std::to_string(spec.nchannels) +
                              " channel(s); a scene image needs three (RGB or XYZ)");
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1)
        throw Error(path, "not a 2D image");
    // The colour channels are the first three that are not alpha: an R, G, A image has two
    // colour channels and is refused, rather than its alpha read as blue.
    int colour[3], found = 0;
    for (int c = 0; c < spec.nchannels && found < 3; ++c) {
        if (c != spec.alpha_channel) colour[found++] = c;
    }
    if (found < 3) {
        std::string names;
        for (int c = 0; c < spec.nchannels; ++c) names += (c ? ", " : "") + std::string(spec.channel_name(c));
        throw Error(path, "has channels " + names + ": a scene image needs three colour channels (RGB or XYZ) besides alpha");
    }
    const std::size_t width = static_cast<std::size_t>(spec.width), height = static_cast<std::size_t>(spec.height);
    const std::size_t all = static_cast<std::size_t>(spec.nchannels);
    std::vector<float> file_pixels(width * height * all);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeFloat, file_pixels.data()))
        throw Error(path, "cannot read the pixels: " + first_line(in->geterror()));

    FloatImage image;
    image.width = width;
    image.height = height;
    const bool alpha = spec.alpha_channel >= 0 && spec.alpha_channel < spec.nchannels;
    image.channels = alpha ? 4 : 3;
    image.pixels.resize(width * height * static_cast<std::size_t>(image.channels));
    for (std::size_t p = 0; p < width * height; ++p) {
        const float* src = &file_pixels[p * all];
        float* dst = &image.pixels[p * static_cast<std::size_t>(image.channels)];
        dst[0] = src[colour[0]], dst[1] = src[colour[1]], dst[2] = src[colour[2]];
        if (alpha) dst[3] = src[spec.alpha_channel];
    }
    return image;
}

void write_png_8bit(AtomicOutput& atomic, std::size_t width, std::size_t height, int channels,
                    const std::vector<std::uint8_t>& bytes, const std::vector<std::pair<std::string, std::string>>& attributes) {
    const std::string& path = atomic.final_path();
    if (channels != 3 && channels != 4) throw Error(path, "a PNG here has 3 or 4 channels, not " + std::to_string(channels));
    if (width == 0 || height == 0 || bytes.size() != width * height * static_cast<std::size_t>(channels))
        throw Error(path, "image size and pixel count disagree (or the image is empty)");
    constexpr std::size_t kMaxSide = 1u << 20;  // PNG and OIIO take int sizes; no real image is larger
    if (width > kMaxSide || height > kMaxSide) throw Error(path, "image too large for PNG");

    // OpenImageIO writes through the proxy into the temporary, never opening a file by name.
    // Declared before `out`, so that it outlives the writes `out` makes when destroyed unclosed.
    AtomicOutputProxy<OIIO::Filesystem::IOProxy> proxy(atomic);
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("png");
    if (!out) throw Error(path, "this build of OpenImageIO cannot write PNG: " + first_line(OIIO::geterror()));
    if (!out->set_ioproxy(&proxy)) throw Error(path, "this build of OpenImageIO cannot write PNG through a proxy");
    OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height), channels, OIIO::TypeUInt8);
    if (channels == 4) {
        spec.alpha_channel = 3;
        spec.attribute("oiio:UnassociatedAlpha", 1);  // already straight: store as is
    }
    spec.attribute("Software", "npf");
    for (const auto& a : attributes) spec.attribute(a.first, a.second);
    if (!out->open(atomic.temporary_path(), spec)) atomic.fail("cannot create output", first_line(out->geterror()));
    if (!out->write_image(OIIO::TypeUInt8, bytes.data()))
        atomic.fail("cannot write the pixels", first_line(out->geterror()));
    if (!out->close()) atomic.fail("cannot finish output", first_line(out->geterror()));
}

void write_png_8bit(const std::string& path, std::size_t width, std::size_t height, int channels,
                    const std::vector<std::uint8_t>& bytes, const std::vector<std::pair<std::string, std::string>>& attributes) {
    AtomicOutput atomic(path);
    write_png_8bit(atomic, width, height, channels, bytes, attributes);
    atomic.commit();
}

void write_display_png(AtomicOutput& atomic, const FloatImage& image, const DisplayTransform& transform) {
    const std::string& path = atomic.final_path();
    const int nc = image.channels;
    if (nc != 3 && nc != 4)
        throw Error(path, "a display image has 3 or 4 channels, not " + std::to_string(nc));
    const std::size_t pixel_count = image.width * image.height;
    if (image.width == 0 || image.height == 0 || image.pixels.size() != pixel_count * static_cast<std::size_t>(nc))
        throw Error(path, "image size and pixel count disagree (or the image is empty)");
    constexpr std::size_t kMaxSide = 1u << 20;  // PNG and OIIO take int sizes; no real image is larger
    if (image.width > kMaxSide || image.height > kMaxSide) throw Error(path, "image too large for PNG");

    std::vector<float> display(image.pixels);
    if (nc == 4) {
        // Premultiplied in, straight out: the display transform is not linear, so unpremultiply
        // first. Pixels with no coverage keep their (zero) colour.
        for (std::size_t p = 0; p < pixel_count; ++p) {
            float* px = &display[p * 4];
            if (px[3] > 0.0f)
                for (int c = 0; c < 3; ++c) px[c] /= px[3];
        }
    }
    transform.apply(display.data(), image.width, image.height, nc);
    std::vector<std::uint8_t> bytes(display.size());
    std::transform(display.begin(), display.end(), bytes.begin(), to_8bit);
    write_png_8bit(atomic, image.width, image.height, nc, bytes, {{"npf:display", transform.display() + " / " + transform.view()}});
}

void write_display_png(const std::string& path, const FloatImage& image, const DisplayTransform& transform) {
    AtomicOutput atomic(path);
    write_display_png(atomic, image, transform);
    atomic.commit();
}

}  // namespace npf::color
