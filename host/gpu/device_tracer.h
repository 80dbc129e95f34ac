// What the wavefront renderer (host/render/) asks of a tracer on the device: closest-hit and
// any-hit traces over device-resident ray arrays, recorded into the renderer's command buffers,
// with their work counters and kernel times. GpuTracer (the BVH kernels, host/gpu/gpu_tracer.h)
// and RayQueryTracer (the driver's traversal, host/gpu/ray_query_tracer.h) implement it.
#pragma once

#include <cstddef>
#include <cstdint>

#include <vulkan/vulkan.h>

#include "gpu/device_tracer_kind.h"
#include "kernels/trace_result.h"
#include "trace/ray_class.h"

namespace hrpp {

class GpuPredictor;
class KernelTimer;
class StorageBuffer;
class TexelView;

class DeviceTracer {
 public:
  virtual ~DeviceTracer() = default;

  // Device-resident rays: hit-all classes (camera, bounce) share one ray and hit array, the
  // hit-any class has its own, grown to hold at least `rays` rays, so other kernels write rays
  // into them and read hits back without a host round trip (gpu::Ray and gpu::Hit records). The
  // references stay valid until a call asks for more. A hit-any record in the hit array is the
  // first occluder found (prim >= 0) or a miss.
  virtual StorageBuffer& ray_buffer(RayClass c, std::size_t rays) = 0;
  virtual StorageBuffer& hit_buffer(RayClass c) = 0;

  // Traces recorded into the caller's command buffer, over ray_buffer(c)[0..count):
  //   begin(c)                before recording (host writes, such as zeroed counters);
  //   record(...)             the trace of `count` rays (known on the host): ray j, or with
  //                           `ray_indices` (a texel view of uint, 4 per texel; --reorder) the
  //                           ray whose index is entry j of the list, its hit written at that
  //                           index;
  //   record_indirect(...)    the trace of as many rays as the uint at `count_offset` of
  //                           `queue` says when the command buffer runs, with the
  //                           VkDispatchIndirectCommand at `args_offset` (workgroups of
  //                           rays_per_workgroup() rays); only when records_indirect(c);
  //   finish(c)               after the submit: checks that every ray finished (throws
  //                           hrpp::Error otherwise), returns the counters (hits left empty).
  // One trace per query kind (hit-all, hit-any) per command buffer. Dispatches are timed with
  // `timer` when given, under {kernel, class} labels (vk/timer_label.h).
  virtual void begin(RayClass c) = 0;
  virtual void record(VkCommandBuffer cmd, RayClass c, std::uint32_t count, KernelTimer* timer,
                      const TexelView* ray_indices = nullptr) = 0;
  virtual void record_indirect(VkCommandBuffer cmd, RayClass c, const StorageBuffer& queue,
                               VkDeviceSize count_offset, VkDeviceSize args_offset,
                               KernelTimer* timer) = 0;
  virtual GpuTraceResult finish(RayClass c) = 0;
  // False when the class's next trace needs its ray count on the host.
  virtual bool records_indirect(RayClass c) const = 0;
  // Rays one workgroup of a trace takes (the indirect dispatch arguments' unit).
  virtual std::uint32_t rays_per_workgroup() const = 0;

  // Runs each kernel once: the first dispatch of a pipeline JIT-compiles on lavapipe, so call
  // this before timing.
  virtual void warm_up() = 0;

  // HRPP's stage (host/hrpp/gpu_predictor.h) when this tracer's traces run through it: the
  // renderer sets how each class probes and reads the tables; nullptr when HRPP is off.
  virtual GpuPredictor* predictor() = 0;
  virtual const GpuPredictor* predictor() const = 0;
};

}  // namespace hrpp
