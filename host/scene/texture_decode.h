// PNG and JPEG bytes (a glTF image, an MTL map_Kd or pbrt imagemap file) decoded to a Texture:
// 8-bit RGBA, rows top to bottom. The header's size is checked before decoding, so a
// decompression bomb (a few bytes that claim gigapixels) is refused before any allocation.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "scene/scene.h"

namespace hrpp {

inline constexpr std::uint32_t kMaxTextureSide = 16384;  // 1 GiB decoded at most

// Throws hrpp::Error "<where>: ..." (one line) when the bytes do not decode.
Texture decode_texture(std::span<const std::uint8_t> bytes, const std::string& name,
                       const std::string& where);

// The file's bytes decoded; "<where>: file F not found or unreadable" when it cannot be read.
Texture read_texture_file(const std::filesystem::path& file, const std::string& where);

}  // namespace hrpp
