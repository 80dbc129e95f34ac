// The built-in EXR encoder (render/exr_encoder.h), read back by OpenImageIO: the size, the
// channels and every float bit for bit, extreme values included, string attributes and
// channels beside R, G and B.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <unistd.h>
#include <vector>

#include "render/exr_encoder.h"

namespace {

using hrpp::encode_exr;

// Writes the encoder's bytes to a file and reads them back through OpenImageIO as RGB floats.
std::vector<float> round_trip(std::uint32_t width, std::uint32_t height,
                              const std::vector<float>& rgb) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("hrpp_exr_test_" + std::to_string(getpid()) + ".exr");
  {
    const std::string bytes = encode_exr(width, height, rgb);
    std::ofstream(file, std::ios::binary)
        .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(file.string());
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  EXPECT_EQ(spec.width, static_cast<int>(width));
  EXPECT_EQ(spec.height, static_cast<int>(height));
  EXPECT_EQ(spec.nchannels, 3);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(spec.channel_name(0), "R");
  EXPECT_EQ(spec.channel_name(1), "G");
  EXPECT_EQ(spec.channel_name(2), "B");
  std::vector<float> back(std::size_t{width} * height * 3, -7.0f);
  EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, back.data())) << in->geterror();
  in->close();
  std::filesystem::remove(file);
  return back;
}

void expect_same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_EQ(std::bit_cast<std::uint32_t>(a[i]), std::bit_cast<std::uint32_t>(b[i]))
        << "float " << i;
}

TEST(ExrEncoder, OnePixel) {
  const std::vector<float> rgb = {0.25f, 0.5f, 0.75f};
  expect_same_bits(round_trip(1, 1, rgb), rgb);
}

TEST(ExrEncoder, RowsAndChannelsInPlaceOnANonSquareImage) {
  const std::uint32_t w = 7, h = 3;
  std::vector<float> rgb(w * h * 3);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<float>(i) + 0.125f;
  expect_same_bits(round_trip(w, h, rgb), rgb);
}

TEST(ExrEncoder, ExtremeValuesKeepTheirBits) {
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> rgb = {-0.0f, -1.5f, 3.4e38f, 1e-45f, 1.17e-38f, inf,
                                  -inf, std::numeric_limits<float>::quiet_NaN(), 65504.0f};
  expect_same_bits(round_trip(3, 1, rgb), rgb);
}

// The provenance hrpp writes into an image (host/app/provenance.h) as OpenImageIO reads it.
TEST(ExrEncoder, StringAttributesReadBack) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("hrpp_exr_attr_test_" + std::to_string(getpid()) + ".exr");
  const std::vector<std::pair<std::string, std::string>> strings = {
      {"hrpp:commit", "0123abc-dirty"}, {"hrpp:command_line", "hrpp render --out 'a b.exr'"},
      {"Software", "hrpp 0123abc-dirty"}};
  {
    const std::string bytes = encode_exr(2, 1, {1, 2, 3, 4, 5, 6}, strings);
    std::ofstream(file, std::ios::binary)
        .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(file.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  for (const auto& [name, value] : strings)
    EXPECT_EQ(in->spec().get_string_attribute(name), value) << name;
  in->close();
  std::filesystem::remove(file);
  EXPECT_THROW(encode_exr(1, 1, {0, 0, 0}, {{std::string(32, 'n'), "too long a name"}}),
               std::invalid_argument);
}

// Channels beside R, G and B (per-pixel statistics, render/ray_stat_layers.h): each read back
// by name, bit for bit; a repeated name, one of R, G, B or an empty one is refused.
TEST(ExrEncoder, ExtraChannelsReadBackByName) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("hrpp_exr_layers_test_" + std::to_string(getpid()) + ".exr");
  const std::uint32_t w = 3, h = 2;
  std::vector<float> rgb(w * h * 3);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = 0.5f * static_cast<float>(i);
  // Not in the file's (sorted) order, and one name before "B" in it.
  const std::vector<hrpp::ImageChannel> extra = {
      {"shadow.rays", {1, 2, 3, 4, 5, 6}},
      {"camera.verified", {-1, -2, 0.25f, 9, 1e-40f, 7}},
      {"A.b", {6, 5, 4, 3, 2, 1}}};
  {
    const std::string bytes = encode_exr(w, h, rgb, {}, extra);
    std::ofstream(file, std::ios::binary)
        .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(file.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec spec = in->spec();
  ASSERT_EQ(spec.nchannels, 6);
  std::vector<float> all(std::size_t{w} * h * 6);
  ASSERT_TRUE(in->read_image(0, 0, 0, 6, OIIO::TypeDesc::FLOAT, all.data())) << in->geterror();
  in->close();
  std::filesystem::remove(file);
  auto channel = [&](const std::string& name) {
    std::vector<float> v;
    for (int c = 0; c < 6; ++c)
      if (spec.channel_name(c) == name)
        for (std::size_t p = 0; p < std::size_t{w} * h; ++p) v.push_back(all[p * 6 + c]);
    return v;
  };
  for (const hrpp::ImageChannel& e : extra) expect_same_bits(channel(e.name), e.values);
  std::vector<float> red;
  for (std::size_t p = 0; p < std::size_t{w} * h; ++p) red.push_back(rgb[p * 3]);
  expect_same_bits(channel("R"), red);
  EXPECT_THROW(encode_exr(1, 1, {0, 0, 0}, {}, {{"x", {1}}, {"x", {2}}}), std::invalid_argument);
  EXPECT_THROW(encode_exr(1, 1, {0, 0, 0}, {}, {{"G", {1}}}), std::invalid_argument);
  EXPECT_THROW(encode_exr(1, 1, {0, 0, 0}, {}, {{"", {1}}}), std::invalid_argument);
}

}  // namespace
