// Closest-hit and any-hit ray queries on the GPU: the BVH uploaded once, rays traced by the
// trace_closest / trace_any kernels with the CPU reference's semantics (host/trace/
// cpu_traversal.h), results, work counters and kernel time read back. The wavefront renderer's
// device tracer (gpu/device_tracer.h, its plumbing gpu/kernel_tracer.h); HRPP stands in front of
// it as a PredictingTracer (host/front/predicting_tracer.h), which traces its queue with
// queue_kernel().
#pragma once

#include <cstddef>
#include <vector>

#include "bvh/gpu_layout.h"
#include "gpu/gpu_tracer_config.h"
#include "gpu/kernel_tracer.h"
#include "kernels/device_bvh.h"
#include "vk/memory_plan.h"

namespace hrpp {

class VulkanContext;

class GpuTracer final : public KernelTracer {
 public:
  // The device buffers a tracer over `bvh` allocates with `resident_rays` rays of each query
  // kind resident (0: none yet): the BVH arrays (read through texel views only), then the ray
  // and hit arrays. For check_fits (vk/memory_plan.h).
  static std::vector<BufferNeed> buffer_needs(const GpuBvh& bvh, std::size_t resident_rays);

  // Checks buffer_needs(bvh, 0) against the device (check_fits, naming the BVH by its triangle
  // count), then uploads the BVH. Throws hrpp::Error when an array exceeds its limit
  // (vk/memory_plan.h) or all of them the device's heap, before anything is allocated.
  GpuTracer(VulkanContext& ctx, const GpuBvh& bvh, const GpuTracerConfig& config = {});
  // The same, freeing each of `bvh`'s arrays once the device holds it (it keeps its bounds).
  struct FreeHostArrays {};
  GpuTracer(VulkanContext& ctx, GpuBvh& bvh, const GpuTracerConfig& config, FreeHostArrays);

  // DeviceTracer: takes a ray order (the indexed kernels); queue_kernel: trace_closest /
  // trace_any, or with skip lists trace_*_skipping, bound to this tracer's BVH.
  QueueTraceKernel queue_kernel(QueryKind kind, bool skip_lists) const override;
  const DeviceBvh* device_bvh() const override { return &device_bvh_; }

 private:
  GpuTracer(VulkanContext& ctx, const GpuBvh& bvh, const GpuTracerConfig& config,
            GpuBvh* release);

  DeviceBvh device_bvh_;
};

}  // namespace hrpp
