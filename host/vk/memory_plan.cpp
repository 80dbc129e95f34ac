#include "vk/memory_plan.h"

#include <algorithm>
#include <vector>

#include "common/bytes.h"
#include "common/error.h"
#include "vk/texel_view.h"
#include "vk/vulkan_context.h"

namespace hrpp {

MemoryLimits memory_limits(const DeviceInfo& d) {
  MemoryLimits m;
  m.storage_range = d.max_storage_buffer_range;
  m.texel_elements = d.max_texel_buffer_elements;
  m.allocation = d.max_memory_allocation_size;
  m.buffer = d.max_buffer_size;
  m.heap = d.heap_bytes;
  m.heap_name = d.heap_capped    ? "memory heap as capped by HRPP_DEVICE_HEAP_MIB"
                : d.heap_budget  ? "memory budget (VK_EXT_memory_budget)"
                : d.heap_is_host ? "memory (a CPU device: the host's physical memory)"
                                 : "memory heap";
  return m;
}

std::uint64_t max_buffer_bytes(BufferBinding binding, const MemoryLimits& limits,
                               std::string* limit_name) {
  struct Limit {
    std::uint64_t bytes;
    const char* name;
  };
  Limit least = {~std::uint64_t{0}, "none"};
  if (binding == BufferBinding::kStorage)
    least = {limits.storage_range, "maxStorageBufferRange"};
  else if (binding == BufferBinding::kTexelOnly)
    least = {limits.texel_elements * TexelView::kTexelBytes,
             "maxTexelBufferElements (16-byte texels)"};
  for (const Limit& l : {Limit{limits.allocation, "maxMemoryAllocationSize"},
                         Limit{limits.buffer, "maxBufferSize"}})
    if (l.bytes < least.bytes) least = l;
  if (limit_name) *limit_name = least.name;
  return least.bytes;
}

void check_buffer(const BufferNeed& need, const MemoryLimits& limits) {
  std::string limit;
  const std::uint64_t most = max_buffer_bytes(need.binding, limits, &limit);
  if (need.bytes > most)
    throw Error(need.name + " is " + format_bytes(need.bytes) + " (" + std::to_string(need.bytes) +
                " bytes), over the device's " + limit + " of " + format_bytes(most) + " (" +
                std::to_string(most) + " bytes)");
}

std::uint64_t total_bytes(std::span<const BufferNeed> needs) {
  std::uint64_t sum = 0;
  for (const BufferNeed& n : needs) sum += n.bytes;
  return sum;
}

void check_fits(const std::string& what, std::span<const BufferNeed> needs,
                const MemoryLimits& limits) {
  for (const BufferNeed& n : needs) check_buffer(n, limits);
  const std::uint64_t sum = total_bytes(needs);
  if (sum <= limits.heap) return;
  // Ties keep the listing order, so the message does not depend on the sort.
  std::vector<const BufferNeed*> largest;
  for (const BufferNeed& n : needs) largest.push_back(&n);
  std::stable_sort(largest.begin(), largest.end(),
                   [](const BufferNeed* a, const BufferNeed* b) { return a->bytes > b->bytes; });
  largest.resize(std::min<std::size_t>(largest.size(), 3));
  std::string top;
  for (const BufferNeed* n : largest)
    top += (top.empty() ? "" : ", ") + n->name + " " + format_bytes(n->bytes);
  throw Error(what + " needs " + format_bytes(sum) + " (" + std::to_string(sum) +
              " bytes) of device memory in " + std::to_string(needs.size()) +
              " buffers (largest: " + top + "), more than the device's " + limits.heap_name +
              " of " + format_bytes(limits.heap) + " (" + std::to_string(limits.heap) + " bytes)");
}

}  // namespace hrpp
