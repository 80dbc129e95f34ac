// The trace kernels' counters block (gpu::TraceCounters, shaders/shared/trace_interface.h): set
// before a trace, read on the host after it (its 64-bit counters are (lo, hi) pairs of 32-bit
// words).
#pragma once

#include <cstdint>

#include <vulkan/vulkan.h>

#include "trace/traversal_counters.h"
#include "trace_interface.h"

namespace hrpp {

class StorageBuffer;

// Before a recorded trace: zeroes `counters` and sets its ray count, on the host's word
// (`count`) or copied from `queue` at `count_offset` (transfers to disjoint bytes, then one
// barrier).
void record_counters_start(VkCommandBuffer cmd, const StorageBuffer& counters,
                           const std::uint32_t* count, const StorageBuffer* queue,
                           VkDeviceSize count_offset);

inline std::uint64_t wide_counter(const gpu::TraceCounters& c, int counter) {
  return static_cast<std::uint64_t>(c.wide[2 * counter]) |
         (static_cast<std::uint64_t>(c.wide[2 * counter + 1]) << 32);
}

// Rays finished, interior nodes, leaves, triangles and hits of one trace.
inline TraversalCounters traversal_counters(const gpu::TraceCounters& c) {
  TraversalCounters t;
  t.rays = wide_counter(c, HRPP_COUNTER_RAYS);
  t.interior_visited = wide_counter(c, HRPP_COUNTER_INTERIOR);
  t.leaves_visited = wide_counter(c, HRPP_COUNTER_LEAVES);
  t.triangles_tested = wide_counter(c, HRPP_COUNTER_TRIANGLES);
  t.hits = wide_counter(c, HRPP_COUNTER_HITS);
  t.interior_steps = wide_counter(c, HRPP_COUNTER_STEPS);
  return t;
}

}  // namespace hrpp
