// Closest-hit and any-hit ray queries on the GPU: the BVH uploaded once, rays traced by the
// trace_closest / trace_any kernels with the CPU reference's semantics (host/trace/
// cpu_traversal.h), results, work counters and kernel time read back. The wavefront renderer's
// device tracer (gpu/device_tracer.h); with HRPP on, the classes that probe trace through the
// HRPP stage (hrpp/gpu_predictor.h), which decides how each trace runs.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <vulkan/vulkan.h>

#include "bvh/gpu_layout.h"
#include "gpu/device_tracer.h"
#include "hrpp/gpu_predictor.h"
#include "gpu/gpu_tracer_config.h"
#include "vk/memory_plan.h"
#include "hrpp/predictor_config.h"
#include "trace/ray_class.h"

namespace hrpp {

class VulkanContext;
struct DeviceInfo;
class StorageBuffer;
class KernelTimer;
class RaySorter;
class TexelView;

class GpuTracer final : public DeviceTracer {
 public:
  // The device buffers a tracer over `bvh` allocates with `resident_rays` rays of each query
  // kind resident (0: none yet): the BVH arrays (read through texel views only), with HRPP on
  // the GpuPredictor's, then the ray and hit arrays. For check_fits (vk/memory_plan.h).
  static std::vector<BufferNeed> buffer_needs(const GpuBvh& bvh, const PredictorConfig& predictor,
                                              std::size_t resident_rays);

  // Checks buffer_needs(bvh, predictor, 0) against the device (check_fits, naming the BVH by its
  // triangle count), then uploads the BVH. Throws hrpp::Error when an array exceeds its limit
  // (vk/memory_plan.h) or all of them the device's heap, before anything is allocated. With
  // predictor.enabled (HRPP on), the classes it names trace through the HRPP stage
  // (host/hrpp/gpu_predictor.h): predict, the trace kernel over the queue, resolve.
  GpuTracer(VulkanContext& ctx, const GpuBvh& bvh, const GpuTracerConfig& config = {},
            const PredictorConfig& predictor = {});
  // The same, freeing each of `bvh`'s arrays once the device holds it (it keeps its bounds).
  struct FreeHostArrays {};
  GpuTracer(VulkanContext& ctx, GpuBvh& bvh, const GpuTracerConfig& config,
            const PredictorConfig& predictor, FreeHostArrays);
  ~GpuTracer() override;
  GpuTracer(GpuTracer&&) noexcept;
  GpuTracer& operator=(GpuTracer&&) noexcept;
  GpuTracer(const GpuTracer&) = delete;
  GpuTracer& operator=(const GpuTracer&) = delete;

  // Traces every ray as rays of class `c` (closest hit, or any hit for shadow rays). Rays
  // beyond one storage buffer's range are traced in several dispatches. Throws hrpp::Error
  // when a dispatch does not finish every ray (loop limiter) or the device is lost.
  // With `sorter` (--reorder), each dispatch's rays are first sorted on the device and traced
  // through the sort's order (record's ray_indices); hits come back in the rays' order and
  // kernel_ms includes the sort. Not when the class predicts (HRPP's stage keeps ray order).
  GpuTraceResult trace(std::span<const gpu::Ray> rays, RayClass c, RaySorter* sorter = nullptr);
  // Rays of a ray file: closest hit as camera rays, any hit as shadow rays.
  GpuTraceResult trace(std::span<const gpu::Ray> rays, QueryKind kind,
                       RaySorter* sorter = nullptr) {
    return trace(rays, ray_file_class(kind), sorter);
  }

  // DeviceTracer (gpu/device_tracer.h). Hit-any records in the hit array: trace() turns them
  // into 0 / -1. With `ray_indices`, HRPP's predicted trace ignores the list (its stage traces
  // in queue order); record_indirect is not for HRPP's batched mode (records_indirect false).
  // rays_per_workgroup: with or without HRPP.
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
  // Traces a few rays with each kernel (with HRPP, the plain kernel and a sample too), then
  // empties the predictor's tables.
  void warm_up() override;
  GpuPredictor* predictor() override;
  const GpuPredictor* predictor() const override;

  // Most rays one dispatch reaches on `device` with `config` (storage-buffer range,
  // texel-buffer size, workgroup count).
  static std::size_t max_dispatch_rays(const DeviceInfo& device, const GpuTracerConfig& config);

  // begin + record + submit + finish of ray_buffer(c)[0..count); with `sorter`, sorted first
  // (as trace()).
  GpuTraceResult trace_resident(std::size_t count, RayClass c, RaySorter* sorter = nullptr);

  const GpuTracerConfig& config() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace hrpp
