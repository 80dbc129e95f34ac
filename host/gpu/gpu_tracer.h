// Closest-hit and any-hit ray queries on the GPU: the BVH uploaded once, rays traced by the
// trace_closest / trace_any kernels with the CPU reference's semantics (host/trace/
// cpu_traversal.h), results, work counters and kernel time read back.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <vulkan/vulkan.h>

#include "bvh/gpu_layout.h"
#include "gpu/gpu_predictor.h"
#include "gpu/gpu_tracer_config.h"
#include "gpu/memory_plan.h"
#include "gpu_types.h"
#include "hrpp/adaptive_predictor.h"
#include "hrpp/predictor_config.h"
#include "hrpp/ray_class.h"
#include "trace/traversal_counters.h"

namespace hrpp {

class VulkanContext;
struct DeviceInfo;
class StorageBuffer;
class KernelTimer;
class RaySorter;
class TexelView;

struct GpuTraceResult {
  std::vector<gpu::Hit> hits;   // one per ray; any-hit: prim 0 occluded, -1 free (t, u, v = 0)
  TraversalCounters counters;   // summed over the ray chunks of the call
  double kernel_ms = 0.0;       // device timestamps around the trace's dispatches (0 when
                                // HRPP runs in batches: many small dispatches)
  double sort_ms = 0.0;         // of kernel_ms, the sort's dispatches (trace() with a sorter)
  bool predicted = false;       // the HRPP stage ran (the class probes)
  std::uint64_t traced = 0;     // rays the trace kernel traced (HRPP: the queue)
  gpu::PredictorCounters predictor{};  // HRPP on: HRPP_PC_* of this call's ray class
  std::uint64_t sampled = 0;    // HRPP sample (Probe::kSample): rays that ran the stage
};

class GpuTracer {
 public:
  // The device buffers a tracer over `bvh` allocates with `resident_rays` rays of each query
  // kind resident (0: none yet): the BVH arrays (read through texel views only), with HRPP on
  // the GpuPredictor's, then the ray and hit arrays. For check_fits (gpu/memory_plan.h).
  static std::vector<BufferNeed> buffer_needs(const GpuBvh& bvh, const PredictorConfig& predictor,
                                              std::size_t resident_rays);

  // Checks buffer_needs(bvh, predictor, 0) against the device (check_fits, naming the BVH by its
  // triangle count), then uploads the BVH. Throws hrpp::Error when an array exceeds its limit
  // (gpu/memory_plan.h) or all of them the device's heap, before anything is allocated. With
  // predictor.enabled (HRPP on), the classes it names trace through the HRPP stage
  // (host/gpu/gpu_predictor.h): predict, the trace kernel over the queue, resolve.
  GpuTracer(VulkanContext& ctx, const GpuBvh& bvh, const GpuTracerConfig& config = {},
            const PredictorConfig& predictor = {});
  ~GpuTracer();
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

  // Device-resident rays (the wavefront renderer, host/render/): hit-all classes (camera,
  // bounce) share one ray and hit array, the hit-any class has its own, grown to hold at least
  // `rays` rays, so other kernels write rays into them and read hits back without a host round
  // trip. The references stay valid until a call asks for more. A hit-any record in the hit
  // array is the first occluder found (prim >= 0) or a miss; trace() turns it into 0 / -1.
  StorageBuffer& ray_buffer(RayClass c, std::size_t rays);
  StorageBuffer& hit_buffer(RayClass c);

  // Traces recorded into the caller's command buffer, over ray_buffer(c)[0..count):
  //   begin(c)                before recording: zeroes the class's HRPP counters (host write);
  //   record(...)             the trace of `count` rays (known on the host): ray j, or with
  //                           `ray_indices` (a texel view of uint, 4 per texel; --reorder) the
  //                           ray whose index is entry j of the list, its hit written at that
  //                           index (the indexed kernels); HRPP's predicted trace ignores the
  //                           list (its stage traces in queue order); or
  //   record_indirect(...)    the trace of as many rays as the uint at `count_offset` of
  //                           `queue` says when the command buffer runs, with the
  //                           VkDispatchIndirectCommand at `args_offset` (workgroups of
  //                           rays_per_workgroup() rays); not in HRPP's batched mode;
  //   finish(c)               after the submit: checks that every ray finished (throws
  //                           hrpp::Error naming the loop limiter otherwise), returns the
  //                           counters (hits left empty) and HRPP counters since begin.
  // One trace per query kind (hit-all, hit-any) per command buffer. Dispatches are timed with
  // `timer` when given, under {kernel, class} labels (hrpp/timer_label.h).
  void begin(RayClass c);
  void record(VkCommandBuffer cmd, RayClass c, std::uint32_t count, KernelTimer* timer,
              const TexelView* ray_indices = nullptr);
  void record_indirect(VkCommandBuffer cmd, RayClass c, const StorageBuffer& queue,
                       VkDeviceSize count_offset, VkDeviceSize args_offset, KernelTimer* timer);
  GpuTraceResult finish(RayClass c);
  // False when the class's trace needs its ray count on the host (HRPP's batched mode).
  bool records_indirect(RayClass c) const;
  // Rays one workgroup of a trace takes, with or without HRPP (indirect dispatch arguments).
  std::uint32_t rays_per_workgroup() const;
  // Most rays one dispatch reaches on `device` with `config` (storage-buffer range,
  // texel-buffer size, workgroup count).
  static std::size_t max_dispatch_rays(const DeviceInfo& device, const GpuTracerConfig& config);

  // begin + record + submit + finish of ray_buffer(c)[0..count); with `sorter`, sorted first
  // (as trace()).
  GpuTraceResult trace_resident(std::size_t count, RayClass c, RaySorter* sorter = nullptr);

  // Traces a few rays with each kernel: the first dispatch of a pipeline JIT-compiles on
  // lavapipe, so call this before timing.
  void warm_up();

  const GpuTracerConfig& config() const;
  // HRPP's configuration; nullptr when the tracer has no predictor (HRPP off).
  const PredictorConfig* predictor_config() const;

  // HRPP on: how class `c` traces through the HRPP stage from the next record on (the adaptive
  // predictor's switch; initially every class the configuration names at Probe::kAll). A sample
  // (not in batched mode) runs the stage over every PredictorConfig::sample-th ray, then the
  // plain trace over every ray: the hits are HRPP off's, the HRPP counters the sample's.
  void set_probing(RayClass c, Probe mode);
  Probe probing(RayClass c) const;
  // HRPP on: what the class's table holds now; empty every table.
  TableOccupancy predictor_occupancy(RayClass c) const;
  void clear_predictor();
  // HRPP on: count what full traversals would visit (savings %) in the next traces; doubles
  // their work, so time with it off.
  void set_count_baseline(bool on);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace hrpp
