#include "kernels/trace_counters.h"

#include <cstddef>

#include "vk/compute_pipeline.h"
#include "vk/storage_buffer.h"

namespace hrpp {

void record_counters_start(VkCommandBuffer cmd, const StorageBuffer& counters,
                           const std::uint32_t* count, const StorageBuffer* queue,
                           VkDeviceSize count_offset) {
  gpu::TraceCounters start{};
  if (count) {
    start.ray_count = *count;
    vkCmdUpdateBuffer(cmd, counters.handle(), 0, sizeof start, &start);
  } else {
    constexpr VkDeviceSize at = offsetof(gpu::TraceCounters, ray_count);
    constexpr VkDeviceSize word = sizeof(std::uint32_t);
    vkCmdUpdateBuffer(cmd, counters.handle(), 0, at, &start);
    vkCmdUpdateBuffer(cmd, counters.handle(), at + word, sizeof start - at - word,
                      reinterpret_cast<const char*>(&start) + at + word);
    record_copy(cmd, *queue, count_offset, counters, at, word);
  }
  transfer_compute_barrier(cmd);
}

}  // namespace hrpp
