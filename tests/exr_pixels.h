// The pixel data of an EXR that hrpp wrote, for comparing two images bit for bit without their
// headers (whose attributes name the command line and the sample count): decoded with
// OpenImageIO where the build has it (its writer compresses), else hrpp's own uncompressed
// encoder's scanline blocks (render/exr_encoder.cpp), taken whole.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#if defined(HRPP_TEST_HAVE_OIIO)
#include <OpenImageIO/imageio.h>
#endif

#include "cli_runner.h"

namespace hrpp::test {

// The RGB floats of `file`, as bytes; "" when it cannot be read. `width` x `height` pixels.
inline std::string exr_pixels(const std::filesystem::path& file, int width, int height) {
#if defined(HRPP_TEST_HAVE_OIIO)
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(file.string());
  if (!in) return "";
  std::vector<float> px(static_cast<std::size_t>(width) * height * 3);
  if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.data())) return "";
  return std::string(reinterpret_cast<const char*>(px.data()), px.size() * sizeof(float));
#else
  const std::string b = read_file(file);
  const std::size_t blocks = static_cast<std::size_t>(height) * (8 + width * 3 * 4);
  return b.size() < blocks ? "" : b.substr(b.size() - blocks);
#endif
}

}  // namespace hrpp::test
