// A minimal OpenEXR encoder: one part, scanlines, no compression, channels R, G, B (and any
// more) as 32-bit floats. It is what `hrpp render` writes to .exr in a build without OpenImageIO
// (HRPP_WITH_OIIO=OFF: a portable binary for a machine without Debian's packages). A build with
// OpenImageIO writes .exr through OpenImageIO (ZIP compressed) and only tests this encoder
// against it.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "render/image_output.h"

namespace hrpp {

// rgb: width × height × 3 linear floats, rows top down (width, height ≥ 1); `strings`: header
// attributes of type string, name and value (a name of at most 31 bytes, as OpenEXR 1 readers
// expect); `extra`: channels beside R, G, B (names unique, none of them R, G or B). The file's
// bytes.
std::string encode_exr(std::uint32_t width, std::uint32_t height, const std::vector<float>& rgb,
                       const std::vector<std::pair<std::string, std::string>>& strings = {},
                       const std::vector<ImageChannel>& extra = {});

}  // namespace hrpp
