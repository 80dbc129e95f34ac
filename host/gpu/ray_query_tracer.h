// Closest-hit and any-hit queries answered by the driver's own traversal (VK_KHR_ray_query): the
// scene's triangles in the driver's acceleration structure (vk/acceleration_structure.h), traced
// by trace_rayquery_closest / trace_rayquery_any (shaders/lib/ray_query_kernel.glsl) with the BVH
// kernels' ray and hit formats and rules. A second device tracer (gpu/device_tracer.h) beside
// GpuTracer, chosen with --tracer rayquery. The driver's node work is invisible: its counters
// hold rays and hits only. With HRPP on, a PredictingTracer (host/front/predicting_tracer.h)
// stands in front of it, the setting of the hardware proposals: the prediction is verified on
// the project's BVH (the stage uploads it), a verified hit-any prediction answers the ray
// without a query, a verified closest hit (exact mode) queues the ray with tmax shortened to
// its t, and the queue is traced by ray queries (queue_kernel). Rays in their own order (no
// --reorder).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "bvh/gpu_layout.h"
#include "gpu/gpu_tracer_config.h"
#include "gpu/kernel_tracer.h"
#include "vk/acceleration_structure.h"
#include "vk/memory_plan.h"

namespace hrpp {

class VulkanContext;

class RayQueryTracer final : public KernelTracer {
 public:
  // Builds the acceleration structures from `bvh`'s triangle records (primitive i: triangle id
  // i; ids no record holds are inactive). config.rays_per_invocation as the BVH kernels'.
  // Throws hrpp::Error when the context has no ray queries (VulkanOptions::ray_query) or a
  // build fails.
  RayQueryTracer(VulkanContext& ctx, const GpuBvh& bvh, const GpuTracerConfig& config = {});

  // The buffers the tracer allocates that are known before its build: the triangles' vertices
  // (the build's input) and with `resident_rays` the ray and hit arrays. The acceleration
  // structures' sizes are the driver's, known once built (each buffer is checked against the
  // heap as it is made).
  static std::vector<BufferNeed> buffer_needs(const GpuBvh& bvh, std::size_t resident_rays);

  // DeviceTracer. No ray order: the driver traces rays as they lie (a ray index list is
  // refused). check_rays names the first ray with a negative tmin (Vulkan's ray queries start
  // at tmin >= 0). queue_kernel: trace_rayquery_*, bound to the structure; skip lists are
  // refused (the BVH kernels' alone). No device_bvh.
  QueueTraceKernel queue_kernel(QueryKind kind, bool skip_lists) const override;
  const DeviceBvh* device_bvh() const override { return nullptr; }
  void check_rays(std::span<const gpu::Ray> rays) const override;

  // The driver's structures: build time and memory.
  const AccelerationStructureStats& structure() const { return structure_.stats(); }

 private:
  AccelerationStructure structure_;
};

}  // namespace hrpp
