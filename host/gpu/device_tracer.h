// What the wavefront renderer (host/render/) asks of a tracer on the device: closest-hit and
// any-hit traces over device-resident ray arrays, recorded into the renderer's command buffers,
// with their work counters and kernel times. GpuTracer (the BVH kernels, host/gpu/gpu_tracer.h)
// and RayQueryTracer (the driver's traversal, host/gpu/ray_query_tracer.h) implement it.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/device_tracer_kind.h"
#include "gpu_types.h"
#include "hrpp_types.h"
#include "hrpp/ray_class.h"
#include "trace/traversal_counters.h"

namespace hrpp {

class GpuPredictor;
class KernelTimer;
class StorageBuffer;
class TexelView;

// What one trace of a ray class did, read back after its submit.
struct GpuTraceResult {
  std::vector<gpu::Hit> hits;  // GpuTracer::trace only: one per ray; any-hit: prim 0
                               // occluded, -1 free (t, u, v = 0)
  TraversalCounters counters;  // summed over the ray chunks of the call
  double kernel_ms = 0.0;      // device timestamps around the trace's dispatches (0 when
                               // HRPP runs in batches: many small dispatches)
  double sort_ms = 0.0;        // of kernel_ms, the sort's dispatches (trace() with a sorter)
  bool predicted = false;      // the HRPP stage ran (the class probes)
  std::uint64_t traced = 0;    // rays the trace kernel traced (HRPP: the queue)
  gpu::PredictorCounters predictor{};  // HRPP on: HRPP_PC_* of this call's ray class
  std::uint64_t sampled = 0;           // HRPP sample (Probe::kSample): rays that ran the stage
};

// The records a hit-any trace leaves in a ray file (hrpp trace): prim 0 occluded, -1 free.
inline void to_occlusion_records(std::span<gpu::Hit> hits) {
  for (gpu::Hit& h : hits) h = gpu::Hit{h.prim >= 0 ? 0 : -1, 0.0f, 0.0f, 0.0f};
}

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
  // `timer` when given, under {kernel, class} labels (hrpp/timer_label.h).
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

  // HRPP's stage (host/gpu/gpu_predictor.h) when this tracer's traces run through it: the
  // renderer sets how each class probes and reads the tables; nullptr when HRPP is off.
  virtual GpuPredictor* predictor() = 0;
  virtual const GpuPredictor* predictor() const = 0;
};

}  // namespace hrpp
