// The HRPP stage on the GPU (host side). A predicted trace of a ray class is three dispatches
// in one command buffer:
//   hrpp_predict   hash, probe the class's table, verify the predicted nodes; a true positive
//                  writes its answer, every other ray is appended to a compacted queue
//   trace kernel   the very kernel HRPP off runs (trace_closest / trace_any), over the queue,
//                  dispatched indirectly from the queue's size
//   hrpp_resolve   the queued rays' answers into the class's hit array; inserts for those
//                  that hit (or, in the deterministic batches, requests that hrpp_insert
//                  applies in ray order)
// The three ray classes' tables lie in one set of buffers (a slice each); camera and bounce
// rays (hit-all) share a queue, shadow rays (hit-any) have their own.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <vulkan/vulkan.h>

#include "bvh/gpu_layout.h"
#include "gpu/memory_plan.h"
#include "hrpp/predictor_config.h"
#include "hrpp/predictor_stats.h"
#include "hrpp/ray_class.h"
#include "hrpp_interface.h"
#include "trace/traversal_counters.h"
#include "trace_interface.h"

namespace hrpp {

class VulkanContext;
class ComputePipeline;
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

// What a predicted trace did, read back after the submit.
struct PredictedTrace {
  TraversalCounters counters;           // the whole class: verification + the queue's trace
  gpu::PredictorCounters predictor{};   // HRPP_PC_* of the class since begin()
  std::uint64_t queued = 0;             // rays the trace kernel traced
};

class GpuPredictor {
 public:
  // The buffers the predictor allocates for `bvh` and `capacity` queued rays per query kind: the
  // node-of-triangle array (a storage buffer: 4 bytes per triangle), each predicting class's
  // table and the queues. For check_fits (gpu/memory_plan.h).
  static std::vector<BufferNeed> buffer_needs(const GpuBvh& bvh, const PredictorConfig& config,
                                              std::size_t capacity);

  // Throws hrpp::Error when the device lacks 64-bit integer atomics or the table exceeds a
  // storage buffer (naming the table and the limit), or the configuration is invalid.
  GpuPredictor(VulkanContext& ctx, const GpuBvh& bvh, const PredictorConfig& config,
               const TexelView& nodes, const TexelView& leaves, const TexelView& triangles);
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

  // Before recording a class's traces: zeroes its predictor counters (host write).
  void begin(RayClass c);
  // Records the predicted trace of the class's rays, kernels timed under {kernel, class}
  // labels (hrpp/timer_label.h). `clock`: use stamp of ray 0 (LRU). Not in batched mode.
  void record(VkCommandBuffer cmd, RayClass c, const RayCountSource& count,
              const gpu::TracePushConstants& trace_pc, std::uint32_t clock, KernelTimer* timer);
  // Records the HRPP stage over a sample of the class's rays (every config().sample-th), its
  // kernels timed in Phase::kSample: the adaptive predictor's sample frame, which then traces
  // every ray with the plain kernel. Then one hrpp_predict dispatch over no ray, timed in
  // Phase::kSampleEmpty: the fixed cost of a dispatch, which weighs 1/sample as much per ray in a
  // frame that predicts every ray. Not in batched mode.
  void record_sample(VkCommandBuffer cmd, RayClass c, const RayCountSource& count,
                     const gpu::TracePushConstants& trace_pc, std::uint32_t clock,
                     KernelTimer* timer);
  // Deterministic order (config().batch = K > 0): per batch of K rays a predict, trace and
  // resolve that defers its inserts, then hrpp_insert applying them in ray order. Untimed.
  void record_batches(VkCommandBuffer cmd, RayClass c, std::uint32_t count,
                      const gpu::TracePushConstants& trace_pc, std::uint32_t clock);
  // After the submit: checks that every ray was answered (throws hrpp::Error naming the loop
  // limiter otherwise) and returns what the class's trace did.
  // `sampled`: the trace was record_sample's (its sample answered, not every ray).
  PredictedTrace finish(RayClass c, bool sampled = false) const;

  // Rays one workgroup of hrpp_predict takes: every lane, or one per subgroup in serial mode,
  // times rays_per_invocation. The trace kernel over the queue takes the same.
  std::uint32_t rays_per_workgroup(std::uint32_t rays_per_invocation) const;
  // Reads the class's table back and counts what it holds (empty for a class that does not
  // predict: it has no table).
  TableOccupancy occupancy(RayClass c) const;
  // Empties every table.
  void clear();
  // Turns the counting of full traversals (PredictorConfig::count_baseline) on or off.
  void set_count_baseline(bool on);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace hrpp
