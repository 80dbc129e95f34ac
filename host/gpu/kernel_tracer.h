// What the two device tracers share (gpu/gpu_tracer.h, gpu/ray_query_tracer.h): per query kind
// the resident ray and hit arrays, one trace kernel and its counters, and where the tracer
// traces a ray order the kernel's indexed twin; recorded, checked, timed and warmed up the same
// way. A tracer of this kind differs only in its kernels and what it binds to them (the BVH's
// arrays, or the driver's acceleration structure).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "bvh/aabb.h"
#include "gpu/device_tracer.h"
#include "gpu/gpu_tracer_config.h"

namespace hrpp {

struct DeviceInfo;

class KernelTracer : public DeviceTracer {
 public:
  ~KernelTracer() override;

  // DeviceTracer (gpu/device_tracer.h). record: with `ray_indices`, the indexed kernel, which a
  // tracer without one refuses (hrpp::Error). Hit-any records in the hit array: trace() turns
  // them into 0 / -1. warm_up: a few rays with each kernel.
  StorageBuffer& ray_buffer(RayClass c, std::size_t rays) override;
  StorageBuffer& hit_buffer(RayClass c) override;
  ResidentRays& resident(RayClass c) override;
  const ResidentRays& resident(RayClass c) const override;
  void begin(RayClass c) override;
  void record(VkCommandBuffer cmd, RayClass c, std::uint32_t count, KernelTimer* timer,
              const TexelView* ray_indices = nullptr) override;
  void record_indirect(VkCommandBuffer cmd, RayClass c, const StorageBuffer& queue,
                       VkDeviceSize count_offset, VkDeviceSize args_offset,
                       KernelTimer* timer) override;
  GpuTraceResult finish(RayClass c) override;
  bool records_indirect(RayClass c) const override;
  bool takes_ray_order(RayClass c) const override;
  std::uint32_t rays_per_workgroup() const override;
  std::size_t chunk_rays() const override;
  void warm_up() override;
  VulkanContext& context() const override;
  KernelTimer& timer() override;
  gpu::TracePushConstants push_constants() const override;
  const char* kernel_label(RayClass c) const override;

  // The configuration with the device's defaults filled in.
  const GpuTracerConfig& config() const;

  // Most rays one dispatch reaches on `device` with `config` (storage-buffer range,
  // texel-buffer size, workgroup count).
  static std::size_t max_dispatch_rays(const DeviceInfo& device, const GpuTracerConfig& config);

 protected:
  // Warm-up rays through the centre of `bounds` (the scene's).
  KernelTracer(VulkanContext& ctx, const GpuTracerConfig& config, const Aabb& bounds);
  KernelTracer(KernelTracer&&) noexcept;
  KernelTracer& operator=(KernelTracer&&) noexcept;

  // The trace kernel of `kind`, bound to the scene, whose bindings name its slots for the
  // rays, hits and counters; with `indexed`, its twin over a ray index list (the same slots and
  // the list at HRPP_TRACE_BINDING_RAY_INDICES), timed under the same label. The counters'
  // buffer is named "<kind> `counters_name`". Call once per query kind in the constructor.
  void set_kernels(QueryKind kind, const std::string& counters_name, QueueTraceKernel kernel,
                   std::optional<ComputePipeline> indexed = std::nullopt);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace hrpp
