#include "render/exr_encoder.h"

#include <bit>
#include <cstring>
#include <stdexcept>
#include <string_view>

namespace hrpp {

namespace {

// OpenEXR stores every number little-endian.
static_assert(std::endian::native == std::endian::little);

template <typename T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

void put_attribute(std::string& out, std::string_view name, std::string_view type,
                   const std::string& value) {
  out.append(name).push_back('\0');
  out.append(type).push_back('\0');
  put<std::int32_t>(out, static_cast<std::int32_t>(value.size()));
  out.append(value);
}

std::string channel_list() {
  std::string list;
  for (const char* name : {"B", "G", "R"}) {  // channels in alphabetical order
    list.append(name).push_back('\0');
    put<std::int32_t>(list, 2);  // FLOAT
    put<std::uint32_t>(list, 0);  // pLinear and three reserved bytes
    put<std::int32_t>(list, 1);  // x sampling
    put<std::int32_t>(list, 1);  // y sampling
  }
  list.push_back('\0');
  return list;
}

std::string header(std::uint32_t width, std::uint32_t height,
                   const std::vector<std::pair<std::string, std::string>>& strings) {
  std::string box;
  for (const std::uint32_t v : {0u, 0u, width - 1, height - 1})
    put<std::int32_t>(box, static_cast<std::int32_t>(v));
  std::string one, centre;
  put<float>(one, 1.0f);
  put<float>(centre, 0.0f);
  put<float>(centre, 0.0f);
  std::string out;
  put<std::uint32_t>(out, 20000630);  // magic number
  put<std::uint32_t>(out, 2);         // version 2, single-part scanline file
  put_attribute(out, "channels", "chlist", channel_list());
  put_attribute(out, "compression", "compression", std::string(1, '\0'));  // none
  put_attribute(out, "dataWindow", "box2i", box);
  put_attribute(out, "displayWindow", "box2i", box);
  put_attribute(out, "lineOrder", "lineOrder", std::string(1, '\0'));  // increasing y
  put_attribute(out, "pixelAspectRatio", "float", one);
  put_attribute(out, "screenWindowCenter", "v2f", centre);
  put_attribute(out, "screenWindowWidth", "float", one);
  for (const auto& [name, value] : strings) {
    if (name.empty() || name.size() > 31 || name.find('\0') != std::string::npos)
      throw std::invalid_argument("EXR attribute name \"" + name + "\": 1 to 31 bytes, no NUL");
    put_attribute(out, name, "string", value);
  }
  out.push_back('\0');
  return out;
}

}  // namespace

std::string encode_exr(std::uint32_t width, std::uint32_t height, const std::vector<float>& rgb,
                       const std::vector<std::pair<std::string, std::string>>& strings) {
  std::string out = header(width, height, strings);
  const std::size_t line_bytes = std::size_t{width} * 3 * sizeof(float);
  const std::size_t block_bytes = 2 * sizeof(std::int32_t) + line_bytes;
  std::uint64_t offset = out.size() + std::size_t{height} * sizeof(std::uint64_t);
  for (std::uint32_t y = 0; y < height; ++y, offset += block_bytes) put<std::uint64_t>(out, offset);
  out.reserve(out.size() + height * block_bytes);
  for (std::uint32_t y = 0; y < height; ++y) {
    put<std::int32_t>(out, static_cast<std::int32_t>(y));
    put<std::int32_t>(out, static_cast<std::int32_t>(line_bytes));
    for (int c = 2; c >= 0; --c)  // B, G, R: each channel's whole line in turn
      for (std::uint32_t x = 0; x < width; ++x)
        put<float>(out, rgb[(std::size_t{y} * width + x) * 3 + c]);
  }
  return out;
}

}  // namespace hrpp
