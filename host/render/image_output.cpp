#include "render/image_output.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <string>
#include <system_error>

#ifdef HRPP_HAVE_OIIO
#include <OpenImageIO/imageio.h>
#endif

#include "common/error.h"
#include "common/interrupt.h"
#include "render/exr_encoder.h"

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

bool is_exr(const std::filesystem::path& file) { return lower_extension(file) == ".exr"; }

void check_image_format(const std::filesystem::path& file) {
  const std::string ext = lower_extension(file);
  if (ext != ".exr" && ext != ".png")
    throw Error(file.string() + ": unknown image format \"" + ext + "\" (use .exr or .png)");
#ifndef HRPP_HAVE_OIIO
  if (ext == ".png")
    throw Error(file.string() + ": this build has no OpenImageIO (HRPP_WITH_OIIO=OFF): use .exr");
#endif
}

namespace {

// Writes through a temporary that keeps the extension (OpenImageIO picks the format from it) and
// renames it to the target: an error never leaves a partial file. The temporary's name holds
// the process id, so two processes writing one target never share it (the last rename wins, a
// whole file either way); a second signal removes it (common/interrupt.h).
class TempImage {
 public:
  explicit TempImage(const std::filesystem::path& file)
      : file_(file),
        tmp_(file.parent_path() / (file.stem().string() + ".partial-" + std::to_string(::getpid()) +
                                   file.extension().string())) {
    set_file_being_written(tmp_.c_str());
  }
  ~TempImage() {
    set_file_being_written(nullptr);
    std::error_code ec;
    if (!done_) std::filesystem::remove(tmp_, ec);
  }
  const std::filesystem::path& path() const { return tmp_; }
  Error fail(const std::string& why) const {
    return Error(file_.string() + ": cannot write image: " + why);
  }
  void commit() {
    std::error_code ec;
    std::filesystem::rename(tmp_, file_, ec);
    if (ec) throw fail(ec.message());
    done_ = true;
  }

 private:
  std::filesystem::path file_, tmp_;
  bool done_ = false;
};

#ifdef HRPP_HAVE_OIIO
// R, G, B and the extra channels interleaved, pixel by pixel.
std::vector<float> interleave(const std::vector<float>& rgb,
                              const std::vector<ImageChannel>& channels) {
  const std::size_t pixels = rgb.size() / 3, n = 3 + channels.size();
  std::vector<float> out(pixels * n);
  for (std::size_t p = 0; p < pixels; ++p) {
    for (std::size_t c = 0; c < 3; ++c) out[p * n + c] = rgb[p * 3 + c];
    for (std::size_t c = 0; c < channels.size(); ++c) out[p * n + 3 + c] = channels[c].values[p];
  }
  return out;
}

void write_oiio(const TempImage& tmp, bool exr, std::uint32_t width, std::uint32_t height,
                const std::vector<float>& rgb, const ImageAttributes& attributes,
                const std::vector<ImageChannel>& channels) {
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(tmp.path().string());
  if (!out) throw tmp.fail(OIIO::geterror());
  OIIO::ImageSpec spec(static_cast<int>(width), static_cast<int>(height),
                       3 + static_cast<int>(channels.size()),
                       exr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  for (std::size_t c = 0; c < channels.size(); ++c) spec.channelnames[3 + c] = channels[c].name;
  spec.alpha_channel = -1;  // a fourth channel is not alpha
  if (!exr) spec.attribute("oiio:ColorSpace", "sRGB");
  for (const auto& [name, value] : attributes) spec.attribute(name, value);
  if (!out->open(tmp.path().string(), spec)) throw tmp.fail(out->geterror());
  bool ok;
  if (exr) {
    ok = out->write_image(OIIO::TypeDesc::FLOAT,
                          channels.empty() ? rgb.data() : interleave(rgb, channels).data());
  } else {
    std::vector<std::uint8_t> bytes(rgb.size());
    for (std::size_t i = 0; i < rgb.size(); ++i)
      bytes[i] = static_cast<std::uint8_t>(std::lround(255.0f * linear_to_srgb(rgb[i])));
    ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
  }
  if (!ok) {
    const std::string why = out->geterror();
    out->close();
    throw tmp.fail(why);
  }
  if (!out->close()) throw tmp.fail(out->geterror());
}
#else
void write_exr(const TempImage& tmp, std::uint32_t width, std::uint32_t height,
               const std::vector<float>& rgb, const ImageAttributes& attributes,
               const std::vector<ImageChannel>& channels) {
  const std::string bytes = encode_exr(width, height, rgb, attributes, channels);
  std::ofstream out(tmp.path(), std::ios::binary);
  if (!out) throw tmp.fail("cannot create " + tmp.path().string());
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw tmp.fail("write failed");
}
#endif

}  // namespace

void write_image(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height,
                 const std::vector<float>& rgb, const ImageAttributes& attributes,
                 const std::vector<ImageChannel>& channels) {
  check_image_format(file);
  const std::size_t pixels = std::size_t{width} * height;
  bool sizes_match = rgb.size() == pixels * 3;
  for (const ImageChannel& c : channels) sizes_match = sizes_match && c.values.size() == pixels;
  if (!sizes_match)
    throw Error(file.string() + ": image data does not match " + std::to_string(width) + "x" +
                std::to_string(height));
  if (!channels.empty() && !is_exr(file))
    throw Error(file.string() + ": only .exr holds channels beside R, G and B");
  TempImage tmp(file);
#ifdef HRPP_HAVE_OIIO
  write_oiio(tmp, is_exr(file), width, height, rgb, attributes, channels);
#else
  write_exr(tmp, width, height, rgb, attributes, channels);  // check_image_format refused the rest
#endif
  tmp.commit();
}

}  // namespace hrpp
