// What the wavefront renderer (host/render/) and the harness ask of a tracer on the device:
// closest-hit and any-hit traces over device-resident ray arrays, recorded into the caller's
// command buffers, with their work counters and kernel times. GpuTracer (the BVH kernels,
// gpu/gpu_tracer.h) and RayQueryTracer (the driver's traversal, gpu/ray_query_tracer.h)
// implement it, and so does PredictingTracer (host/front/predicting_tracer.h), HRPP's stage in
// front of either: a tracer gets HRPP by being wrapped, and knows nothing of it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <vulkan/vulkan.h>

#include "bvh/aabb.h"
#include "gpu/device_tracer_kind.h"
#include "kernels/queue_trace_kernel.h"
#include "kernels/trace_result.h"
#include "trace/ray_class.h"
#include "trace_interface.h"

namespace hrpp {

class DeviceBvh;
class GpuPredictor;
class KernelTimer;
class RaySorter;
class StorageBuffer;
class TexelView;
class VulkanContext;
struct ResidentRays;

class DeviceTracer {
 public:
  virtual ~DeviceTracer() = default;

  // Device-resident rays: hit-all classes (camera, bounce) share one ray and hit array, the
  // hit-any class has its own, grown to hold at least `rays` rays, so other kernels write rays
  // into them and read hits back without a host round trip (gpu::Ray and gpu::Hit records). The
  // references stay valid until a call asks for more. A hit-any record in the hit array is the
  // first occluder found (prim >= 0) or a miss. resident(c): the arrays as they are, with the
  // texel views the kernels read them by.
  virtual StorageBuffer& ray_buffer(RayClass c, std::size_t rays) = 0;
  virtual StorageBuffer& hit_buffer(RayClass c) = 0;
  virtual ResidentRays& resident(RayClass c) = 0;
  virtual const ResidentRays& resident(RayClass c) const = 0;

  // Traces recorded into the caller's command buffer, over ray_buffer(c)[0..count):
  //   begin(c)                before recording (host writes, such as zeroed counters);
  //   record(...)             the trace of `count` rays (known on the host): ray j, or with
  //                           `ray_indices` (a texel view of uint, 4 per texel; --reorder; only
  //                           where takes_ray_order(c)) the ray whose index is entry j of the
  //                           list, its hit written at that index;
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
  // Whether record() takes a ray index list for class `c` now.
  virtual bool takes_ray_order(RayClass c) const = 0;
  // Rays one workgroup of a trace takes (the indirect dispatch arguments' unit).
  virtual std::uint32_t rays_per_workgroup() const = 0;
  // Most rays one trace dispatch takes (trace() cuts host rays into chunks of this many).
  virtual std::size_t chunk_rays() const = 0;

  // Runs each kernel once: the first dispatch of a pipeline JIT-compiles on lavapipe, so call
  // this before timing.
  virtual void warm_up() = 0;

  // What a stage in front of this tracer (PredictingTracer) builds on: the context, the timer
  // trace() uses, the push constants of this tracer's trace kernels, a trace kernel of its own
  // for the stage's queue (`skip_lists`: one that starts from a skip list; hrpp::Error where the
  // tracer has none), the BVH arrays on the device (nullptr: it has none, the stage uploads its
  // own), and the kernel a submit names in its errors.
  virtual VulkanContext& context() const = 0;
  virtual KernelTimer& timer() = 0;
  virtual gpu::TracePushConstants push_constants() const = 0;
  virtual QueueTraceKernel queue_kernel(QueryKind kind, bool skip_lists) const = 0;
  virtual const DeviceBvh* device_bvh() const = 0;
  virtual const char* kernel_label(RayClass c) const = 0;
  // Throws hrpp::Error naming the first ray this tracer cannot take (trace() asks first).
  virtual void check_rays(std::span<const gpu::Ray> rays) const { (void)rays; }

  // HRPP's stage when this tracer's traces run through it (PredictingTracer): the renderer sets
  // how each class probes and reads the tables; nullptr for a plain tracer.
  virtual GpuPredictor* predictor() { return nullptr; }
  virtual const GpuPredictor* predictor() const { return nullptr; }

  // Host rays: every ray as a ray of class `c` (closest hit, or any hit for shadow rays), in
  // dispatches of at most chunk_rays(); hit-any records come back as 0 (occluded) / -1. With
  // `sorter` (--reorder), each dispatch's rays are first sorted on the device and traced
  // through the sort's order where takes_ray_order(c); hits come back in the rays' order and
  // kernel_ms includes the sort. Throws hrpp::Error when a dispatch does not finish every ray
  // (loop limiter) or the device is lost.
  GpuTraceResult trace(std::span<const gpu::Ray> rays, RayClass c, RaySorter* sorter = nullptr);
  // Rays of a ray file: closest hit as camera rays, any hit as shadow rays.
  GpuTraceResult trace(std::span<const gpu::Ray> rays, QueryKind kind,
                       RaySorter* sorter = nullptr) {
    return trace(rays, ray_file_class(kind), sorter);
  }
  // begin + record + submit + finish of ray_buffer(c)[0..count); with `sorter`, sorted first
  // (as trace()).
  GpuTraceResult trace_resident(std::size_t count, RayClass c, RaySorter* sorter = nullptr);
};

// Throws hrpp::Error when `count` rays exceed `tracer`'s resident arrays of class `c` or one
// dispatch (record), or when they hold none yet (record_indirect: count 0).
void check_resident(const DeviceTracer& tracer, RayClass c, std::size_t count);
void check_sized(const DeviceTracer& tracer, RayClass c);

// The rays a tracer's warm_up() traces: a workgroup of rays through the centre of `bounds`.
std::vector<gpu::Ray> warm_up_rays(const Aabb& bounds);

}  // namespace hrpp
