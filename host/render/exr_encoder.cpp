#include "render/exr_encoder.h"

#include <algorithm>
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

// A channel of the file: its name and its value at pixel p, values[p * stride].
struct Channel {
  std::string name;
  const float* values;
  std::size_t stride;
};

// R, G, B and the extra channels, in the file's order (names sorted bytewise, as OpenEXR keeps
// them).
std::vector<Channel> file_channels(const std::vector<float>& rgb,
                                   const std::vector<ImageChannel>& extra) {
  std::vector<Channel> out;
  for (int c = 0; c < 3; ++c) out.push_back({std::string(1, "RGB"[c]), rgb.data() + c, 3});
  for (const ImageChannel& e : extra) {
    if (e.name.empty() || e.name.size() > 31 || e.name.find('\0') != std::string::npos)
      throw std::invalid_argument("EXR channel name \"" + e.name + "\": 1 to 31 bytes, no NUL");
    out.push_back({e.name, e.values.data(), 1});
  }
  std::sort(out.begin(), out.end(),
            [](const Channel& a, const Channel& b) { return a.name < b.name; });
  for (std::size_t i = 1; i < out.size(); ++i)
    if (out[i].name == out[i - 1].name)
      throw std::invalid_argument("EXR channel \"" + out[i].name + "\" twice");
  return out;
}

std::string channel_list(const std::vector<Channel>& channels) {
  std::string list;
  for (const Channel& ch : channels) {
    list.append(ch.name).push_back('\0');
    put<std::int32_t>(list, 2);  // FLOAT
    put<std::uint32_t>(list, 0);  // pLinear and three reserved bytes
    put<std::int32_t>(list, 1);  // x sampling
    put<std::int32_t>(list, 1);  // y sampling
  }
  list.push_back('\0');
  return list;
}

std::string header(std::uint32_t width, std::uint32_t height, const std::vector<Channel>& channels,
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
  put_attribute(out, "channels", "chlist", channel_list(channels));
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
                       const std::vector<std::pair<std::string, std::string>>& strings,
                       const std::vector<ImageChannel>& extra) {
  const std::vector<Channel> channels = file_channels(rgb, extra);
  std::string out = header(width, height, channels, strings);
  const std::size_t line_bytes = std::size_t{width} * channels.size() * sizeof(float);
  const std::size_t block_bytes = 2 * sizeof(std::int32_t) + line_bytes;
  std::uint64_t offset = out.size() + std::size_t{height} * sizeof(std::uint64_t);
  for (std::uint32_t y = 0; y < height; ++y, offset += block_bytes) put<std::uint64_t>(out, offset);
  out.reserve(out.size() + height * block_bytes);
  for (std::uint32_t y = 0; y < height; ++y) {
    put<std::int32_t>(out, static_cast<std::int32_t>(y));
    put<std::int32_t>(out, static_cast<std::int32_t>(line_bytes));
    for (const Channel& ch : channels)  // each channel's whole line in turn
      for (std::uint32_t x = 0; x < width; ++x)
        put<float>(out, ch.values[(std::size_t{y} * width + x) * ch.stride]);
  }
  return out;
}

}  // namespace hrpp
