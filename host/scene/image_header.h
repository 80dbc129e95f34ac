// The pixel size a PNG or JPEG declares in its header, read before decoding: the glTF loader
// refuses a decompression bomb (a small file that claims gigapixels) before stb_image
// allocates its pixels.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace hrpp {

struct ImageHeader {
  std::string format;  // "PNG" or "JPEG"
  std::uint32_t width = 0;
  std::uint32_t height = 0;
};

// PNG: the IHDR chunk (width at byte 16, height at 20). JPEG: the frame header of the first
// start-of-frame marker (SOF0..SOF15 but DHT, JPG and DAC), found by walking the marker
// segments from SOI. Nothing for other formats, or when the header is cut short or the scan
// starts before a frame header (the decoder reports those).
std::optional<ImageHeader> read_image_header(std::span<const std::uint8_t> bytes);

}  // namespace hrpp
