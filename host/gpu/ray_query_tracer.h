// Closest-hit and any-hit queries answered by the driver's own traversal (VK_KHR_ray_query): the
// scene's triangles in the driver's acceleration structure (vk/acceleration_structure.h), traced
// by trace_rayquery_closest / trace_rayquery_any (shaders/lib/ray_query_kernel.glsl) with the BVH
// kernels' ray and hit formats and rules. A second device tracer (gpu/device_tracer.h) beside
// GpuTracer, chosen with --tracer rayquery. The driver's node work is invisible: its counters
// hold rays and hits only. With HRPP on, the HRPP stage (hrpp/gpu_predictor.h) runs in front of
// the driver's traversal, the setting of the hardware proposals: the prediction is verified on
// the project's BVH (uploaded for it), a verified hit-any prediction answers the ray without a
// query, a verified closest hit (exact mode) queues the ray with tmax shortened to its t, and
// the queue is traced by ray queries. Rays in their own order (no --reorder).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "bvh/gpu_layout.h"
#include "gpu/device_tracer.h"
#include "gpu/gpu_tracer_config.h"
#include "hrpp/predictor_config.h"
#include "vk/acceleration_structure.h"
#include "vk/memory_plan.h"

namespace hrpp {

class VulkanContext;
struct DeviceInfo;

class RayQueryTracer final : public DeviceTracer {
 public:
  // The buffers the tracer allocates that are known before its build: the triangles' vertices
  // (the build's input), with HRPP on the project's BVH and the stage's buffers, and with
  // `resident_rays` the ray and hit arrays. The acceleration structures' sizes are the
  // driver's, known once built (each buffer is checked against the heap as it is made).
  static std::vector<BufferNeed> buffer_needs(const GpuBvh& bvh, const PredictorConfig& predictor,
                                              std::size_t resident_rays);

  // Builds the acceleration structures from `bvh`'s triangle records (primitive i: triangle id
  // i; ids no record holds are inactive); with predictor.enabled also uploads `bvh` for the
  // HRPP stage (binary nodes). config.rays_per_invocation as the BVH kernels'. Throws
  // hrpp::Error when the context has no ray queries (VulkanOptions::ray_query) or a build fails.
  RayQueryTracer(VulkanContext& ctx, const GpuBvh& bvh, const GpuTracerConfig& config = {},
                 const PredictorConfig& predictor = {});
  ~RayQueryTracer() override;
  RayQueryTracer(RayQueryTracer&&) noexcept;
  RayQueryTracer& operator=(RayQueryTracer&&) noexcept;
  RayQueryTracer(const RayQueryTracer&) = delete;
  RayQueryTracer& operator=(const RayQueryTracer&) = delete;

  // Every ray as a ray of class `c`, in dispatches of at most max_dispatch_rays; hit-any records
  // come back as 0 (occluded) / -1. Throws hrpp::Error naming the first ray with a negative
  // tmin (Vulkan's ray queries start at tmin >= 0) or when a dispatch does not finish.
  GpuTraceResult trace(std::span<const gpu::Ray> rays, RayClass c);
  GpuTraceResult trace(std::span<const gpu::Ray> rays, QueryKind kind) {
    return trace(rays, ray_file_class(kind));
  }

  // DeviceTracer. `ray_indices` is refused (hrpp::Error): the driver traces rays as they lie.
  StorageBuffer& ray_buffer(RayClass c, std::size_t rays) override;
  StorageBuffer& hit_buffer(RayClass c) override;
  void begin(RayClass c) override;
  void record(VkCommandBuffer cmd, RayClass c, std::uint32_t count, KernelTimer* timer,
              const TexelView* ray_indices = nullptr) override;
  void record_indirect(VkCommandBuffer cmd, RayClass c, const StorageBuffer& queue,
                       VkDeviceSize count_offset, VkDeviceSize args_offset,
                       KernelTimer* timer) override;
  GpuTraceResult finish(RayClass c) override;
  bool records_indirect(RayClass c) const override;
  std::uint32_t rays_per_workgroup() const override;
  void warm_up() override;
  GpuPredictor* predictor() override;
  const GpuPredictor* predictor() const override;

  // The driver's structures: build time and memory.
  const AccelerationStructureStats& structure() const;

  // Most rays one dispatch reaches on `device` with `config` (as GpuTracer's).
  static std::size_t max_dispatch_rays(const DeviceInfo& device, const GpuTracerConfig& config);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace hrpp
