// Opening an image file npf reads as data (environment maps, renders to compare or display), the
// one way: a regular file (a FIFO or /dev/zero would block or never end), of a format known by its
// first bytes (OpenEXR, Radiance HDR, TIFF, PNG, JPEG) and opened by that format's reader alone.
// OpenImageIO's ImageInput::open(name) picks a reader by the name's extension, and some readers
// take parameters from the name itself: a file called `x.null?RES=20000x20000` made OpenImageIO
// 2.4 abort. Sizes are checked before any pixel is read: at most 2^28 pixels, and at most
// 64 times the file's size plus 64 MiB as floats in memory (docs/reliability.md).
#pragma once

#include <OpenImageIO/imageio.h>

#include <memory>
#include <string>

namespace npf::color {

// The opened image, its spec() checked as above. `what` names the kind in messages ("an
// environment map", "an image"). Throws npf::Error naming `path`.
std::unique_ptr<OIIO::ImageInput> open_image_file(const std::string& path, const std::string& what);

}  // namespace npf::color
