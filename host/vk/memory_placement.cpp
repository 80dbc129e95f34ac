#include "vk/memory_placement.h"

#include <functional>
#include <optional>

#include "common/error.h"

namespace hrpp {

namespace {

using namespace memory_flags;

using TypeTest = std::function<bool(std::uint32_t type)>;

bool has(const VkPhysicalDeviceMemoryProperties& mp, std::uint32_t i, VkMemoryPropertyFlags f) {
  return (mp.memoryTypes[i].propertyFlags & f) == f;
}

VkDeviceSize heap_size(const VkPhysicalDeviceMemoryProperties& mp, std::uint32_t i) {
  return mp.memoryHeaps[mp.memoryTypes[i].heapIndex].size;
}

// The first allowed type that passes the first test any allowed type passes.
std::optional<std::uint32_t> first_passing(const VkPhysicalDeviceMemoryProperties& mp,
                                           std::uint32_t allowed,
                                           std::initializer_list<TypeTest> tests) {
  for (const TypeTest& test : tests)
    for (std::uint32_t i = 0; i < mp.memoryTypeCount; ++i)
      if ((allowed & (1u << i)) && test(i)) return i;
  return std::nullopt;
}

// The allowed type of the largest heap among those that pass `test`; on a tie, one that is not
// host-visible, then the lowest index.
std::optional<std::uint32_t> largest_heap(const VkPhysicalDeviceMemoryProperties& mp,
                                          std::uint32_t allowed, const TypeTest& test) {
  std::optional<std::uint32_t> best;
  for (std::uint32_t i = 0; i < mp.memoryTypeCount; ++i) {
    if (!(allowed & (1u << i)) || !test(i)) continue;
    const bool larger = !best || heap_size(mp, i) > heap_size(mp, *best);
    const bool tie_unmapped = best && heap_size(mp, i) == heap_size(mp, *best) &&
                              has(mp, *best, kHost) && !has(mp, i, kHost);
    if (larger || tie_unmapped) best = i;
  }
  return best;
}

std::optional<std::uint32_t> staged_device_type(const VkPhysicalDeviceMemoryProperties& mp,
                                                std::uint32_t allowed) {
  if (auto t = largest_heap(mp, allowed, [&](std::uint32_t i) { return has(mp, i, kLocal); }))
    return t;
  return largest_heap(mp, allowed, [](std::uint32_t) { return true; });
}

std::optional<std::uint32_t> mapped_device_type(const VkPhysicalDeviceMemoryProperties& mp,
                                                std::uint32_t allowed) {
  const std::optional<std::uint32_t> local =
      largest_heap(mp, allowed, [&](std::uint32_t i) { return has(mp, i, kLocal); });
  const VkDeviceSize local_heap = local ? heap_size(mp, *local) : 0;
  return first_passing(
      mp, allowed,
      {[&](std::uint32_t i) {
         return has(mp, i, kHost | kCoherent | kLocal) && heap_size(mp, i) == local_heap;
       },
       [&](std::uint32_t i) { return has(mp, i, kHost | kCoherent) && !has(mp, i, kLocal); },
       [&](std::uint32_t i) { return has(mp, i, kHost | kCoherent); },
       [&](std::uint32_t i) { return has(mp, i, kHost); }});
}

std::optional<std::uint32_t> host_shared_type(const VkPhysicalDeviceMemoryProperties& mp,
                                              std::uint32_t allowed) {
  return first_passing(
      mp, allowed,
      {[&](std::uint32_t i) { return has(mp, i, kHost | kCached | kCoherent); },
       [&](std::uint32_t i) { return has(mp, i, kHost | kCached); },
       [&](std::uint32_t i) { return has(mp, i, kHost | kCoherent) && !has(mp, i, kLocal); },
       [&](std::uint32_t i) { return has(mp, i, kHost | kCoherent); },
       [&](std::uint32_t i) { return has(mp, i, kHost); }});
}

}  // namespace

MemoryMode resolve_memory_mode(MemoryMode requested, VkPhysicalDeviceType device) {
  if (requested != MemoryMode::kAuto) return requested;
  const bool shares_host_memory =
      device == VK_PHYSICAL_DEVICE_TYPE_CPU || device == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU;
  return shares_host_memory ? MemoryMode::kMapped : MemoryMode::kStaged;
}

MemoryTypeChoice choose_memory_type(const VkPhysicalDeviceMemoryProperties& mp,
                                    std::uint32_t allowed, MemoryMode mode, MemoryRole role) {
  if (mode == MemoryMode::kAuto)
    throw Error("choose_memory_type: resolve the memory mode first (resolve_memory_mode)");
  const bool staged = role == MemoryRole::kDevice && mode == MemoryMode::kStaged;
  const std::optional<std::uint32_t> type = role == MemoryRole::kHostShared
                                                ? host_shared_type(mp, allowed)
                                            : staged ? staged_device_type(mp, allowed)
                                                     : mapped_device_type(mp, allowed);
  if (!type)
    throw Error(std::string("the Vulkan device offers no ") +
                (staged ? "memory" : "host-visible memory") + " for " +
                name_in(kMemoryRoleNames, role) + " storage buffers (--memory " +
                name_in(kMemoryModeNames, mode) + ")");
  return {*type, mp.memoryTypes[*type].heapIndex, mp.memoryTypes[*type].propertyFlags, !staged};
}

std::string memory_flags_text(VkMemoryPropertyFlags flags) {
  std::string s;
  const std::pair<VkMemoryPropertyFlags, const char*> names[] = {{kLocal, "device-local"},
                                                                 {kHost, "host-visible"},
                                                                 {kCoherent, "coherent"},
                                                                 {kCached, "cached"}};
  for (const auto& [bit, name] : names)
    if (flags & bit) s += (s.empty() ? "" : ", ") + std::string(name);
  return s.empty() ? "none" : s;
}

}  // namespace hrpp
