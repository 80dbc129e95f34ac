#include "render/image_output.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <system_error>

#include <OpenImageIO/imageio.h>

#include "common/error.h"

namespace hrpp {

float linear_to_srgb(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);  // NaN → 0 below
  if (!(c > 0.0031308f)) return c > 0.0f ? 12.92f * c : 0.0f;
  return 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

namespace {

std::string lower_extension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext;
}

}  // namespace

void check_image_format(const std::filesystem::path& file) {
  const std::string ext = lower_extension(file);
  if (ext != ".exr" && ext != ".png")
    throw Error(file.string() + ": unknown image format \"" + ext + "\" (use .exr or .png)");
}

void write_image(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height,
                 const std::vector<float>& rgb) {
  check_image_format(file);
  const std::string ext = lower_extension(file);
  if (rgb.size() != std::size_t{width} * height * 3)
    throw Error(file.string() + ": image data does not match " + std::to_string(width) + "x" +
                std::to_string(height));
  // The temporary keeps the extension: OpenImageIO picks the format from it.
  const std::filesystem::path tmp =
      file.parent_path() / (file.stem().string() + ".partial" + file.extension().string());
  const auto fail = [&](const std::string& why) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    return Error(file.string() + ": cannot write image: " + why);
  };
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(tmp.string());
  if (!out) throw fail(OIIO::geterror());
  const bool exr = ext == ".exr";
  OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height), 3,
                       exr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!exr) spec.attribute("oiio:ColorSpace", "sRGB");
  if (!out->open(tmp.string(), spec)) throw fail(out->geterror());
  bool ok;
  if (exr) {
    ok = out->write_image(OIIO::TypeDesc::FLOAT, rgb.data());
  } else {
    std::vector<std::uint8_t> bytes(rgb.size());
    for (std::size_t i = 0; i < rgb.size(); ++i)
      bytes[i] = static_cast<std::uint8_t>(std::lround(255.0f * linear_to_srgb(rgb[i])));
    ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
  }
  if (!ok) {
    const std::string why = out->geterror();
    out->close();
    throw fail(why);
  }
  if (!out->close()) throw fail(out->geterror());
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) throw fail(ec.message());
}

}  // namespace hrpp
