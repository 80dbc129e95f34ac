// HRPP in front of a tracer: the paper's picture, a predictor before the traversal. A
// PredictingTracer owns the HRPP stage (host/front/gpu_predictor.h) and any device tracer behind
// it (the BVH kernels, the driver's ray queries), which knows nothing of HRPP, as Embree's filter
// functions or pbrt's aggregates wrap a primitive. A class that probes traces through the stage:
// hrpp_predict, the inner tracer's queue_kernel() over the queue, hrpp_resolve; a class that does
// not (or a sample's full trace) goes to the inner tracer as it is. The resident rays are the
// inner tracer's. The CPU's inline predictor (host/hrpp/inline_predictor.h) is not a wrapper: it
// probes inside one traversal loop per ray, where a front would cost a second pass over the rays.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "bvh/gpu_layout.h"
#include "gpu/device_tracer.h"
#include "front/gpu_predictor.h"
#include "hrpp/predictor_config.h"
#include "kernels/device_bvh.h"

namespace hrpp {

class PredictingTracer final : public DeviceTracer {
 public:
  // The stage's tables are made from `bvh`'s host arrays first, then `make_inner()` builds the
  // tracer behind it (which may free them: it must then have a device_bvh()); the stage
  // verifies on the inner tracer's BVH arrays, or uploads its own from `bvh` where the inner
  // has none. Throws hrpp::Error for a BVH of other than binary nodes (HRPP's predictor tests
  // binary nodes) and as GpuPredictor does.
  PredictingTracer(VulkanContext& ctx, const GpuBvh& bvh, const PredictorConfig& config,
                   const std::function<std::unique_ptr<DeviceTracer>()>& make_inner);
  ~PredictingTracer() override;

  // The tracer behind the stage.
  DeviceTracer& inner() { return *inner_; }
  const DeviceTracer& inner() const { return *inner_; }

  // DeviceTracer. With `ray_indices`, a predicted trace ignores the list (the stage traces in
  // queue order: takes_ray_order is false for a class that probes every ray);
  // record_indirect is not for HRPP's batched mode (records_indirect false). warm_up: every way
  // the adaptive switch may run a class (its first dispatches JIT-compile), then empties the
  // tables.
  StorageBuffer& ray_buffer(RayClass c, std::size_t rays) override;
  StorageBuffer& hit_buffer(RayClass c) override { return inner_->hit_buffer(c); }
  ResidentRays& resident(RayClass c) override { return inner_->resident(c); }
  const ResidentRays& resident(RayClass c) const override { return inner_->resident(c); }
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
  std::size_t chunk_rays() const override { return inner_->chunk_rays(); }
  void warm_up() override;
  VulkanContext& context() const override { return inner_->context(); }
  KernelTimer& timer() override { return inner_->timer(); }
  gpu::TracePushConstants push_constants() const override { return inner_->push_constants(); }
  QueueTraceKernel queue_kernel(QueryKind kind, bool skip_lists) const override {
    return inner_->queue_kernel(kind, skip_lists);
  }
  const DeviceBvh* device_bvh() const override { return inner_->device_bvh(); }
  const char* kernel_label(RayClass c) const override { return inner_->kernel_label(c); }
  void check_rays(std::span<const gpu::Ray> rays) const override { inner_->check_rays(rays); }
  GpuPredictor* predictor() override { return predictor_.get(); }
  const GpuPredictor* predictor() const override { return predictor_.get(); }

 private:
  // Points the stage at the inner tracer's arrays of class `c` when they were reallocated.
  void bind_resident(RayClass c);

  std::unique_ptr<GpuPredictor> predictor_;
  std::unique_ptr<DeviceTracer> inner_;
  DeviceBvh own_bvh_;  // what the stage verifies on when the inner tracer has no BVH arrays
  std::array<std::size_t, 2> bound_bytes_{};  // [index_of(QueryKind)]: ray array bound last
  std::vector<gpu::Ray> probes;               // warm-up rays
};

}  // namespace hrpp
