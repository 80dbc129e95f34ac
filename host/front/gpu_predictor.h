// The HRPP stage on the GPU (host side). A predicted trace of a ray class is three dispatches
// in one command buffer:
//   hrpp_predict   hash, probe the class's table, verify the predicted nodes; a true positive
//                  writes its answer, every other ray is appended to a compacted queue
//   trace kernel   the kernel of the tracer the stage stands in front of (its queue_kernel:
//                  trace_closest / trace_any, or the driver's trace_rayquery_*), over the
//                  queue, dispatched indirectly from the queue's size
//   hrpp_resolve   the queued rays' answers into the class's hit array; inserts for those
//                  that hit (or, in the deterministic batches, requests that hrpp_insert
//                  applies in ray order)
// The three ray classes' tables lie in one set of buffers (a slice each); camera and bounce
// rays (hit-all) share a queue, shadow rays (hit-any) have their own. PredictingTracer
// (host/front/predicting_tracer.h) owns the stage and routes a tracer's traces through it.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <vulkan/vulkan.h>

#include "bvh/gpu_layout.h"
#include "kernels/queue_trace_kernel.h"
#include "kernels/trace_result.h"
#include "vk/memory_plan.h"
#include "hrpp/adaptive_predictor.h"
#include "hrpp/predictor_config.h"
#include "hrpp/predictor_stats.h"
#include "trace/ray_class.h"
#include "hrpp_interface.h"
#include "trace/traversal_counters.h"
#include "trace_interface.h"

namespace hrpp {

class VulkanContext;
class ComputePipeline;
class DeviceBvh;
class KernelTimer;
class StorageBuffer;
class TexelView;

// Where a predicted trace takes its ray count: the host's word, or a uint in a device buffer
// with the VkDispatchIndirectCommand of the predict dispatch (in workgroups of
// GpuPredictor::rays_per_workgroup()).
struct RayCountSource {
  const std::uint32_t* host = nullptr;
  const StorageBuffer* buffer = nullptr;
  VkDeviceSize count_offset = 0;
  VkDeviceSize args_offset = 0;
};

// hrpp_predict's workgroup size on a device of `subgroup_size` lanes (HRPP_SPEC_PREDICT_WORKGROUP):
// one subgroup where that divides the trace kernels' workgroup, else the trace kernels' size.
std::uint32_t predict_workgroup_size(std::uint32_t subgroup_size);

// What a predicted trace did, read back after the submit.
struct PredictedTrace {
  TraversalCounters counters;           // the whole class: verification + the queue's trace
  gpu::PredictorCounters predictor{};   // HRPP_PC_* of the class since begin()
  std::uint64_t queued = 0;             // rays the trace kernel traced
};

class GpuPredictor {
 public:
  // The buffers the predictor allocates for `bvh` and `capacity` queued rays per query kind: the
  // node-of-triangle arrays (read through texel views: 4 bytes per triangle, one per go-up rule of
  // the predicting classes), each predicting class's table and the queues. For check_fits
  // (vk/memory_plan.h).
  static std::vector<BufferNeed> buffer_needs(const GpuBvh& bvh, const PredictorConfig& config,
                                              std::size_t capacity);

  // The tables and the node-of-triangle arrays, read from `bvh`'s host arrays (which may be
  // freed afterwards). Throws hrpp::Error when the device lacks 64-bit integer atomics or the
  // table exceeds a storage buffer (naming the table and the limit), or the configuration is
  // invalid. connect() before the first trace.
  GpuPredictor(VulkanContext& ctx, const GpuBvh& bvh, const PredictorConfig& config);
  // The prediction is verified on `device_bvh` (the same BVH's arrays on the device); each
  // query kind's queue is traced by queue_kernel(kind, skip lists wanted), a kernel of the
  // tracer behind the stage (DeviceTracer::queue_kernel).
  void connect(const DeviceBvh& device_bvh,
               const std::function<QueueTraceKernel(QueryKind, bool)>& queue_kernel);
  ~GpuPredictor();
  GpuPredictor(GpuPredictor&&) noexcept;
  GpuPredictor& operator=(GpuPredictor&&) noexcept;
  GpuPredictor(const GpuPredictor&) = delete;
  GpuPredictor& operator=(const GpuPredictor&) = delete;

  const PredictorConfig& config() const;

  // Points the stage of one query kind at the class arrays it reads rays from and writes hits
  // to, and sizes its queue for `capacity` rays (call again when they are reallocated).
  void bind_rays(QueryKind kind, const TexelView& rays, const TexelView& hits,
                 std::size_t capacity);

  // Routing: how each class's traces run through the stage from the next record on (the
  // adaptive predictor's switch, host/hrpp/adaptive_predictor.h). Initially every class the
  // configuration names probes (Probe::kAll), the others are off for good. A sample (not in
  // batched mode: there it reads as off) runs the stage over every `sample_stride`-th block of
  // rays (0: config().sample), then the tracer's plain trace over every ray: the hits are HRPP
  // off's, the counters the sample's.
  void set_probing(RayClass c, Probe mode, std::uint32_t sample_stride = 0);
  Probe probing(RayClass c) const;
  // False when the class's next trace needs its ray count on the host (batched mode).
  bool records_indirect(RayClass c) const;

  // The tracer's side of a trace of class `c` (host/front/predicting_tracer.cpp):
  //   begin(c)          before recording: zeroes the class's counters (host write) when it probes;
  //   record_trace(...) records the stage as probing(c) says, its use stamps (LRU) continuing
  //                     the class's clock, its kernels timed under {kernel, phase, class}
  //                     labels (vk/timer_label.h). Returns true when the stage answers every
  //                     ray (Probe::kAll), false when the tracer traces them itself (off, or
  //                     after a sample's stage);
  //   recorded(c)       after the submit: how that trace ran the stage;
  //   finish(c)         checks that every ray the stage took was answered (throws hrpp::Error
  //                     naming the loop limiter otherwise) and returns what it did: the whole
  //                     trace for kAll, the sample's for kSample;
  //   advance_clock(c, rays)  then, with the rays of the whole trace.
  // With Probe::kAll a trace is predict → trace of the queue → resolve (config().pilot >= 2:
  // two such rounds, pilots first); in batched mode (config().batch = K > 0) per batch of K
  // rays a round whose inserts are deferred, then hrpp_insert applying them in ray order
  // (untimed, and only with the count on the host). A sample is one round over every
  // config().sample-th ray, timed in Phase::kSample, then one hrpp_predict dispatch over no ray
  // timed in Phase::kSampleEmpty: the fixed cost of a dispatch, which weighs 1/sample as much
  // per ray in a frame that predicts every ray.
  void begin(RayClass c);
  bool record_trace(VkCommandBuffer cmd, RayClass c, const RayCountSource& count,
                    const gpu::TracePushConstants& trace_pc, KernelTimer* timer);
  Probe recorded(RayClass c) const;
  PredictedTrace finish(RayClass c) const;
  void advance_clock(RayClass c, std::uint64_t rays);

  // Rays one workgroup of hrpp_predict takes: every lane, or one per subgroup in serial mode,
  // times rays_per_invocation. The trace kernel over the queue takes the same.
  std::uint32_t rays_per_workgroup(std::uint32_t rays_per_invocation) const;
  // Reads the class's table back and counts what it holds (empty for a class that does not
  // predict: it has no table).
  TableOccupancy occupancy(RayClass c) const;
  // Empties every table and restarts the use clocks.
  void clear();
  // Turns the counting of full traversals (PredictorConfig::count_baseline) on or off.
  void set_count_baseline(bool on);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace hrpp
