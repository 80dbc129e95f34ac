// Where buffers live (--memory): the memory mode, the role of a buffer, and the pure choice of a
// Vulkan memory type for a role from the device's VkPhysicalDeviceMemoryProperties
// (docs/DEVICES.md, "Device memory").
#pragma once

#include <cstdint>
#include <string>

#include <vulkan/vulkan.h>

#include "common/name_table.h"

namespace hrpp {

// staged: the kernels' data in device-local memory, filled and read back through a staging
// buffer (vk/staged_transfer.h); mapped: every buffer host-visible and mapped for its life;
// auto: mapped on a CPU device (lavapipe) or an integrated GPU, staged on the others.
enum class MemoryMode : std::uint8_t { kAuto, kStaged, kMapped };
inline constexpr NameTable<MemoryMode, 3> kMemoryModeNames = {{{MemoryMode::kAuto, "auto"},
                                                               {MemoryMode::kStaged, "staged"},
                                                               {MemoryMode::kMapped, "mapped"}}};

// What a buffer is for. kDevice: data the kernels read and write (BVH, scene arrays, rays, hits,
// path states, predictor tables); kHostShared: small buffers the host reads or writes around
// every submit (trace counters, queue sizes, per-trace parameters): host-visible, host-cached
// where offered, and mapped in every mode.
enum class MemoryRole : std::uint8_t { kDevice, kHostShared };
inline constexpr NameTable<MemoryRole, 2> kMemoryRoleNames = {
    {{MemoryRole::kDevice, "device"}, {MemoryRole::kHostShared, "host_shared"}}};

// The property flags the choice looks at, by short names.
namespace memory_flags {
inline constexpr VkMemoryPropertyFlags kLocal = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
inline constexpr VkMemoryPropertyFlags kHost = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
inline constexpr VkMemoryPropertyFlags kCoherent = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
inline constexpr VkMemoryPropertyFlags kCached = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
}  // namespace memory_flags

// A memory type chosen for a role.
struct MemoryTypeChoice {
  std::uint32_t type = 0;           // index into VkPhysicalDeviceMemoryProperties::memoryTypes
  std::uint32_t heap = 0;           // its heap
  VkMemoryPropertyFlags flags = 0;  // its property flags
  bool mapped = false;              // buffers of the role are mapped (else staged)

  bool coherent() const { return (flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != 0; }
  bool device_local() const { return (flags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) != 0; }
};

// kAuto resolved by the device's type; kStaged and kMapped as they are.
MemoryMode resolve_memory_mode(MemoryMode requested, VkPhysicalDeviceType device);

// The memory type for buffers of `role` that allow `allowed` (a memoryTypeBits mask) under a
// resolved `mode`:
//  - staged, kDevice: the device-local type of the largest heap, one that is not host-visible
//    first (so a small host-visible device-local window, a BAR without resizable BAR, is never
//    used); without device-local types, the largest heap.
//  - mapped, kDevice: host-visible; device-local and coherent only where its heap is the largest
//    device-local heap (unified memory, lavapipe, resizable BAR), else coherent host memory,
//    else any host-visible type.
//  - kHostShared: host-visible; cached and coherent, cached, coherent (host memory before a
//    device-local window), any, in that order.
// Throws hrpp::Error when no allowed type fits.
MemoryTypeChoice choose_memory_type(const VkPhysicalDeviceMemoryProperties& mp,
                                    std::uint32_t allowed, MemoryMode mode, MemoryRole role);

// "device-local, host-visible, coherent, cached" (the flags the choice looks at), or "none".
std::string memory_flags_text(VkMemoryPropertyFlags flags);

}  // namespace hrpp
