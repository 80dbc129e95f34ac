// The memory-type choice of --memory (vk/memory_placement.h) on hand-made
// VkPhysicalDeviceMemoryProperties: a discrete GPU with a 256 MiB host-visible device-local
// window (no resizable BAR), the same with resizable BAR, a CPU device (lavapipe's one type), an
// integrated GPU; and the mode auto resolves to by device type.
#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <utility>

#include "error_of.h"
#include "vk/memory_placement.h"

namespace hrpp {
namespace {

using namespace memory_flags;
constexpr VkDeviceSize kMiB = VkDeviceSize{1} << 20;
constexpr VkDeviceSize kGiB = VkDeviceSize{1} << 30;
constexpr std::uint32_t kAll = ~0u;

// Heaps by size (device-local where the size's flag says so), types by (flags, heap).
VkPhysicalDeviceMemoryProperties memory(
    std::initializer_list<std::pair<VkDeviceSize, bool>> heaps,
    std::initializer_list<std::pair<VkMemoryPropertyFlags, std::uint32_t>> types) {
  VkPhysicalDeviceMemoryProperties mp{};
  for (const auto& [size, local] : heaps)
    mp.memoryHeaps[mp.memoryHeapCount++] = {
        size, local ? VkMemoryHeapFlags{VK_MEMORY_HEAP_DEVICE_LOCAL_BIT} : VkMemoryHeapFlags{0}};
  for (const auto& [flags, heap] : types) mp.memoryTypes[mp.memoryTypeCount++] = {flags, heap};
  return mp;
}

// A discrete GPU without resizable BAR (NVIDIA's usual list): 8 GiB of VRAM, 32 GiB of system
// memory, and a 256 MiB host-visible device-local window, listed first so that a choice by
// flags alone would take it.
const VkPhysicalDeviceMemoryProperties kDiscrete = memory(
    {{8 * kGiB, true}, {32 * kGiB, false}, {256 * kMiB, true}}, {{kLocal | kHost | kCoherent, 2},
                                                                 {kLocal, 0},
                                                                 {kHost | kCoherent, 1},
                                                                 {kHost | kCoherent | kCached, 1}});

// The same with resizable BAR: all of VRAM host-visible.
const VkPhysicalDeviceMemoryProperties kResizableBar =
    memory({{8 * kGiB, true}, {32 * kGiB, false}}, {{kLocal, 0},
                                                    {kLocal | kHost | kCoherent, 0},
                                                    {kHost | kCoherent, 1},
                                                    {kHost | kCoherent | kCached, 1}});

// lavapipe (Mesa 22.3): one heap, one type with every flag.
const VkPhysicalDeviceMemoryProperties kCpu =
    memory({{2 * kGiB, true}}, {{kLocal | kHost | kCoherent | kCached, 0}});

// An integrated GPU (Intel's usual list): one device-local heap that is system memory.
const VkPhysicalDeviceMemoryProperties kIntegrated = memory(
    {{16 * kGiB, true}},
    {{kLocal, 0}, {kLocal | kHost | kCoherent, 0}, {kLocal | kHost | kCoherent | kCached, 0}});

std::uint32_t type_of(const VkPhysicalDeviceMemoryProperties& mp, MemoryMode mode, MemoryRole role,
                      std::uint32_t allowed = kAll) {
  return choose_memory_type(mp, allowed, mode, role).type;
}

TEST(MemoryPlacement, AutoIsMappedWhereTheDeviceSharesHostMemory) {
  EXPECT_EQ(resolve_memory_mode(MemoryMode::kAuto, VK_PHYSICAL_DEVICE_TYPE_CPU),
            MemoryMode::kMapped);
  EXPECT_EQ(resolve_memory_mode(MemoryMode::kAuto, VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU),
            MemoryMode::kMapped);
  EXPECT_EQ(resolve_memory_mode(MemoryMode::kAuto, VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU),
            MemoryMode::kStaged);
  EXPECT_EQ(resolve_memory_mode(MemoryMode::kAuto, VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU),
            MemoryMode::kStaged);
  for (MemoryMode m : {MemoryMode::kStaged, MemoryMode::kMapped})
    EXPECT_EQ(resolve_memory_mode(m, VK_PHYSICAL_DEVICE_TYPE_CPU), m);
}

TEST(MemoryPlacement, StagedOnADiscreteGpuNeverUsesTheSmallHostVisibleWindow) {
  const MemoryTypeChoice device =
      choose_memory_type(kDiscrete, kAll, MemoryMode::kStaged, MemoryRole::kDevice);
  EXPECT_EQ(device.type, 1u);  // VRAM, not the 256 MiB window of type 0
  EXPECT_EQ(device.heap, 0u);
  EXPECT_FALSE(device.mapped);
  EXPECT_TRUE(device.device_local());
  // Where VRAM's type is not allowed, the window is the device-local memory left; with no
  // device-local type allowed, the largest heap.
  EXPECT_EQ(type_of(kDiscrete, MemoryMode::kStaged, MemoryRole::kDevice, 0b1101), 0u);
  EXPECT_EQ(type_of(kDiscrete, MemoryMode::kStaged, MemoryRole::kDevice, 0b1100), 2u);
  // What auto resolves to on it.
  EXPECT_EQ(type_of(kDiscrete,
                    resolve_memory_mode(MemoryMode::kAuto, VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU),
                    MemoryRole::kDevice),
            1u);
}

TEST(MemoryPlacement, MappedOnADiscreteGpuMapsSystemMemoryWhereTheWindowIsSmall) {
  const MemoryTypeChoice device =
      choose_memory_type(kDiscrete, kAll, MemoryMode::kMapped, MemoryRole::kDevice);
  EXPECT_EQ(device.type, 2u);  // coherent system memory: the window holds 256 MiB of 8 GiB
  EXPECT_TRUE(device.mapped);
  EXPECT_TRUE(device.coherent());
  // With resizable BAR all of VRAM is host-visible: mapped maps it, staged takes the type that
  // is not host-visible in the same heap.
  EXPECT_EQ(type_of(kResizableBar, MemoryMode::kMapped, MemoryRole::kDevice), 1u);
  EXPECT_EQ(type_of(kResizableBar, MemoryMode::kStaged, MemoryRole::kDevice), 0u);
  // Only the window allowed: mapped takes it rather than fail.
  EXPECT_EQ(type_of(kDiscrete, MemoryMode::kMapped, MemoryRole::kDevice, 0b0001), 0u);
}

TEST(MemoryPlacement, HostSharedBuffersAreCachedHostMemoryInEveryMode) {
  for (MemoryMode m : {MemoryMode::kStaged, MemoryMode::kMapped}) {
    const MemoryTypeChoice shared = choose_memory_type(kDiscrete, kAll, m, MemoryRole::kHostShared);
    EXPECT_EQ(shared.type, 3u);
    EXPECT_TRUE(shared.mapped);
    EXPECT_EQ(type_of(kResizableBar, m, MemoryRole::kHostShared), 3u);
    EXPECT_EQ(type_of(kIntegrated, m, MemoryRole::kHostShared), 2u);
    // No cached type allowed: coherent host memory, not the window; the window only alone.
    EXPECT_EQ(type_of(kDiscrete, m, MemoryRole::kHostShared, 0b0111), 2u);
    EXPECT_EQ(type_of(kDiscrete, m, MemoryRole::kHostShared, 0b0001), 0u);
  }
}

TEST(MemoryPlacement, ACpuDeviceHasOneTypeForEverything) {
  for (MemoryMode m : {MemoryMode::kStaged, MemoryMode::kMapped})
    for (MemoryRole r : {MemoryRole::kDevice, MemoryRole::kHostShared})
      EXPECT_EQ(type_of(kCpu, m, r), 0u);
  EXPECT_FALSE(choose_memory_type(kCpu, kAll, MemoryMode::kStaged, MemoryRole::kDevice).mapped);
  EXPECT_TRUE(choose_memory_type(kCpu, kAll, MemoryMode::kMapped, MemoryRole::kDevice).mapped);
}

TEST(MemoryPlacement, AnIntegratedGpuMapsItsDeviceLocalMemory) {
  EXPECT_EQ(type_of(kIntegrated, MemoryMode::kMapped, MemoryRole::kDevice), 1u);
  EXPECT_EQ(type_of(kIntegrated, MemoryMode::kStaged, MemoryRole::kDevice), 0u);
}

TEST(MemoryPlacement, NoFittingTypeIsAOneLineError) {
  const VkPhysicalDeviceMemoryProperties device_only = memory({{4 * kGiB, true}}, {{kLocal, 0}});
  const std::string e = test::error_of(
      [&] { choose_memory_type(device_only, kAll, MemoryMode::kMapped, MemoryRole::kDevice); });
  EXPECT_NE(e.find("no host-visible memory for device storage buffers (--memory mapped)"),
            std::string::npos)
      << e;
  EXPECT_EQ(type_of(device_only, MemoryMode::kStaged, MemoryRole::kDevice), 0u);
  EXPECT_NE(test::error_of([&] {
              choose_memory_type(device_only, kAll, MemoryMode::kStaged, MemoryRole::kHostShared);
            }),
            "");
  EXPECT_NE(test::error_of(
                [&] { choose_memory_type(kCpu, 0u, MemoryMode::kStaged, MemoryRole::kDevice); }),
            "");
}

TEST(MemoryPlacement, FlagsAreNamed) {
  EXPECT_EQ(memory_flags_text(kLocal | kHost | kCoherent | kCached),
            "device-local, host-visible, coherent, cached");
  EXPECT_EQ(memory_flags_text(0), "none");
}

}  // namespace
}  // namespace hrpp
