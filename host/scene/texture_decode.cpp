// decode_texture(): stb_image through tinygltf's LoadImageData (the one decoder the glTF loader
// uses too), 16-bit channels cut to their high byte.
#include "scene/texture_decode.h"

#include <tiny_gltf.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <vector>

#include "common/error.h"
#include "scene/image_header.h"

namespace hrpp {

Texture decode_texture(std::span<const std::uint8_t> bytes, const std::string& name,
                       const std::string& where) {
  if (bytes.empty() || bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw Error(where + " has an invalid size");
  }
  const auto header = read_image_header(bytes);
  if (header && (header->width > kMaxTextureSide || header->height > kMaxTextureSide)) {
    throw Error(where + ": " + header->format + " of " + std::to_string(header->width) + " x " +
                std::to_string(header->height) + " pixels, larger than " +
                std::to_string(kMaxTextureSide) + " on a side");
  }
  tinygltf::Image decoded;
  std::string err, warn;
  if (!tinygltf::LoadImageData(&decoded, 0, &err, &warn, 0, 0, bytes.data(),
                               static_cast<int>(bytes.size()), nullptr)) {
    for (char& c : err) {
      if (static_cast<unsigned char>(c) < 0x20) c = ' ';  // stb's messages end in a newline
    }
    while (!err.empty() && err.back() == ' ') err.pop_back();
    throw Error(where + ": " + err);
  }
  Texture tex;
  tex.name = name;
  tex.width = decoded.width;
  tex.height = decoded.height;
  const std::size_t texels = static_cast<std::size_t>(tex.width) * tex.height;
  if (decoded.component != 4 || (decoded.bits != 8 && decoded.bits != 16) ||
      decoded.image.size() < texels * 4 * (decoded.bits / 8)) {
    throw Error(where + ": unexpected decoded format");
  }
  if (decoded.bits == 8) {
    tex.rgba.assign(decoded.image.begin(), decoded.image.begin() + texels * 4);
  } else {  // 16-bit channels in host order: keep the high byte
    tex.rgba.resize(texels * 4);
    for (std::size_t i = 0; i < texels * 4; ++i) {
      std::uint16_t v;
      std::memcpy(&v, decoded.image.data() + 2 * i, 2);
      tex.rgba[i] = static_cast<std::uint8_t>(v >> 8);
    }
  }
  return tex;
}

Texture read_texture_file(const std::filesystem::path& file, const std::string& where) {
  std::ifstream in(file, std::ios::binary);
  std::error_code ec;
  if (!in || std::filesystem::is_directory(file, ec)) {
    throw Error(where + ": file " + file.string() + " not found or unreadable");
  }
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  return decode_texture(bytes, file.filename().string(), where);
}

}  // namespace hrpp
