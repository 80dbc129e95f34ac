// The device-resident ray and hit arrays of one query kind, as both device tracers
// (gpu/gpu_tracer.h, gpu/ray_query_tracer.h) keep them, and their trace of host rays in chunks.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "gpu/device_tracer.h"
#include "vk/memory_plan.h"
#include "vk/storage_buffer.h"
#include "vk/texel_view.h"

namespace hrpp {

class VulkanContext;

// The arrays (gpu::Ray and gpu::Hit records) and the texel views the kernels read them by,
// grown on demand.
struct ResidentRays {
  StorageBuffer rays, hits;
  TexelView ray_view, hit_view;

  // Makes room for `n` rays of `kind` (freeing the old arrays first: one at a time in the
  // heap). True when it reallocated them: the kernels must be bound to the new views.
  bool reserve(VulkanContext& ctx, QueryKind kind, std::size_t n);

  // Both query kinds' arrays for `rays` resident rays each, for check_fits (vk/memory_plan.h).
  static std::vector<BufferNeed> needs(std::size_t rays);
};

// A trace of host rays in chunks of at most `chunk`: per chunk, upload into resident(n)'s rays,
// trace(n), download its hits; the figures summed, hit-any answers as the ray file's records.
GpuTraceResult trace_in_chunks(std::span<const gpu::Ray> rays, RayClass c, std::size_t chunk,
                               const std::function<ResidentRays&(std::size_t)>& resident,
                               const std::function<GpuTraceResult(std::size_t)>& trace);

}  // namespace hrpp
