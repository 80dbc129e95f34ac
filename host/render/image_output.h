// Rendered images to files through OpenImageIO, format from the extension: .exr keeps linear
// float radiance; .png (and other 8-bit formats) are tone mapped: clamped to [0, 1] and encoded
// with the sRGB transfer curve. An .exr may hold more channels beside R, G and B (ImageChannel:
// per-pixel statistics, render/ray_stat_layers.h). Written next to the target and renamed, so
// an error never leaves a partial file. A build without OpenImageIO (HRPP_WITH_OIIO=OFF) writes .exr with
// its own encoder (render/exr_encoder.h) and refuses .png.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hrpp {

// String metadata, name and value: EXR string attributes, PNG text chunks (tEXt, the name its
// keyword; OpenImageIO maps a few names, ImageDescription to Description, say).
using ImageAttributes = std::vector<std::pair<std::string, std::string>>;

// A float channel beside R, G and B: its name ("layer.channel", OpenEXR's layer convention) and
// width × height values, rows top down.
struct ImageChannel {
  std::string name;
  std::vector<float> values;
};

// rgb: width × height × 3 linear floats, rows top down; `channels`: .exr only. Throws
// hrpp::Error naming the file.
void write_image(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height,
                 const std::vector<float>& rgb, const ImageAttributes& attributes = {},
                 const std::vector<ImageChannel>& channels = {});

// Whether the file's extension is .exr (any case): the one format that holds ImageChannels.
bool is_exr(const std::filesystem::path& file);

// Throws hrpp::Error naming the file when its extension is neither .exr nor .png.
void check_image_format(const std::filesystem::path& file);

// The sRGB transfer curve of a clamped linear value (IEC 61966-2-1).
float linear_to_srgb(float linear);

}  // namespace hrpp
