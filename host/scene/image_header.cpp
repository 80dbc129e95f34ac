#include "scene/image_header.h"

#include <cstring>

namespace hrpp {
namespace {

std::uint32_t big_endian(std::span<const std::uint8_t> b, std::size_t at, std::size_t n) {
  std::uint32_t v = 0;
  for (std::size_t k = 0; k < n; ++k) v = v << 8 | b[at + k];
  return v;
}

std::optional<ImageHeader> png_header(std::span<const std::uint8_t> b) {
  if (b.size() < 24 || std::memcmp(b.data(), "\x89PNG\r\n\x1a\n", 8) != 0) return std::nullopt;
  return ImageHeader{"PNG", big_endian(b, 16, 4), big_endian(b, 20, 4)};
}

// SOF0..SOF15 carry a frame header; C4 (DHT), C8 (JPG) and CC (DAC) share the range.
bool is_start_of_frame(std::uint8_t marker) {
  return marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
}

// Markers without a length: TEM and RST0..RST7 (SOI and EOI never precede a frame header).
bool is_standalone(std::uint8_t marker) {
  return marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7);
}

std::optional<ImageHeader> jpeg_header(std::span<const std::uint8_t> b) {
  if (b.size() < 4 || b[0] != 0xFF || b[1] != 0xD8) return std::nullopt;
  std::size_t at = 2;
  while (at + 1 < b.size()) {
    if (b[at] != 0xFF) return std::nullopt;  // not a marker: corrupt
    const std::uint8_t marker = b[at + 1];
    if (marker == 0xFF) {  // fill byte
      ++at;
      continue;
    }
    if (is_standalone(marker)) {
      at += 2;
      continue;
    }
    if (at + 4 > b.size() || marker == 0xDA) return std::nullopt;  // cut short, or scan first
    // Frame header: length (2), precision (1), height (2), width (2).
    if (is_start_of_frame(marker)) {
      if (at + 9 > b.size()) return std::nullopt;
      return ImageHeader{"JPEG", big_endian(b, at + 7, 2), big_endian(b, at + 5, 2)};
    }
    at += 2 + big_endian(b, at + 2, 2);
  }
  return std::nullopt;
}

}  // namespace

std::optional<ImageHeader> read_image_header(std::span<const std::uint8_t> bytes) {
  if (auto png = png_header(bytes)) return png;
  return jpeg_header(bytes);
}

}  // namespace hrpp
