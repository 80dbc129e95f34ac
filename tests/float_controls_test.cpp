// Float subnormals on the device (host/vk/float_controls.h): every kernel's SPIR-V with the
// DenormPreserve execution mode added is a valid module by spirv-val (SPIRV-Tools, the
// independent witness; skipped where it is not installed), and the device's
// shaderDenormPreserveFloat32, read here straight from Vulkan, is what hrpp reports on its
// device line and in render --stats. On lavapipe, which does not report the property, the
// kernels run unchanged; their bit-for-bit checks against C++ (light_transport_test's offset
// rays, cpu_render_test) cover subnormals there.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "common/error.h"
#include "vk/embedded_shaders.h"
#include "vk/float_controls.h"
#include "vk/vulkan_context.h"
#include "gpu_test_context.h"

namespace hrpp {
namespace {

using test::context;

constexpr std::uint32_t kOpExecutionMode = 16;
constexpr std::uint32_t kDenormPreserve = 4459;

// The operands of every OpExecutionMode DenormPreserve in `spirv` (the bit width).
std::vector<std::uint32_t> denorm_preserve_widths(std::span<const std::uint32_t> spirv) {
  std::vector<std::uint32_t> widths;
  for (std::size_t i = 5; i < spirv.size(); i += spirv[i] >> 16) {
    if ((spirv[i] & 0xFFFFu) == kOpExecutionMode && spirv[i + 2] == kDenormPreserve)
      widths.push_back(spirv[i + 3]);
    if ((spirv[i] >> 16) == 0) break;
  }
  return widths;
}

// spirv-val's verdict on `spirv` for Vulkan 1.2: 0 valid.
int spirv_val(std::span<const std::uint32_t> spirv, const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / "kernel.spv";
  std::ofstream(file, std::ios::binary)
      .write(reinterpret_cast<const char*>(spirv.data()),
             static_cast<std::streamsize>(spirv.size_bytes()));
  return std::system(("spirv-val --target-env vulkan1.2 " + file.string()).c_str());
}

class FloatControls : public test::CliTest {};

TEST_F(FloatControls, EveryKernelWithDenormPreserveIsValidSpirv) {
  if (std::system("spirv-val --version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "spirv-val (spirv-tools) not installed";
  for (const auto& [kernel, name] : kKernelNames) {
    const std::span<const std::uint32_t> plain = embedded_spirv(kernel);
    const std::vector<std::uint32_t> preserving = with_denorm_preserve(plain);
    EXPECT_TRUE(denorm_preserve_widths(plain).empty()) << name;
    EXPECT_EQ(denorm_preserve_widths(preserving), std::vector<std::uint32_t>{32u}) << name;
    EXPECT_EQ(preserving.size(), plain.size() + 6) << name;  // a capability and a mode
    EXPECT_EQ(spirv_val(preserving, dir_), 0) << name;
  }
}

TEST(FloatControlsInput, RejectsWhatIsNotSpirv) {
  const std::vector<std::uint32_t> junk = {1, 2, 3, 4, 5, 6};
  EXPECT_THROW(with_denorm_preserve(junk), Error);
  std::vector<std::uint32_t> cut(embedded_spirv(Kernel::trace_any).begin(),
                                 embedded_spirv(Kernel::trace_any).begin() + 12);
  cut.back() = 0xFFFF0011u;  // an instruction running past the end
  EXPECT_THROW(with_denorm_preserve(cut), Error);
}

TEST_F(FloatControls, DeviceReportsWhetherItKeepsSubnormals) {
  VkPhysicalDeviceFloatControlsProperties floats{};
  floats.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FLOAT_CONTROLS_PROPERTIES;
  VkPhysicalDeviceProperties2 p2{};
  p2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  p2.pNext = &floats;
  vkGetPhysicalDeviceProperties2(context().physical_device(), &p2);
  const DeviceInfo& info = context().info();
  EXPECT_EQ(info.denorm_preserve, floats.shaderDenormPreserveFloat32 == VK_TRUE);
  std::printf("%s\n", info.summary().c_str());

  const std::string stats = (dir_ / "stats.json").string();
  const test::CliResult r = run("render builtin:cornell --size 8x8 --spp 1 --out " +
                                (dir_ / "i.exr").string() + " --stats " + stats);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find(info.denormals_text()), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(test::read_file(stats));
  EXPECT_EQ(j["device"]["denorm_preserve"].get<bool>(), info.denorm_preserve);
}

}  // namespace
}  // namespace hrpp
