// The HRPP predictor on the GPU (host side): the hit-all and hit-any tables
// (shaders/lib/hrpp_table.glsl), their parameters and counters, the node-of-triangle array, and
// the recording of predicted trace dispatches: one dispatch as usual, or (deterministic order,
// PredictorConfig::batch = K) per batch of K rays a trace dispatch that defers its inserts and an
// hrpp_insert dispatch that applies them in ray order, all in one command buffer.
#pragma once

#include <cstdint>
#include <memory>

#include <vulkan/vulkan.h>

#include "bvh/gpu_layout.h"
#include "hrpp/predictor_config.h"
#include "hrpp/predictor_stats.h"
#include "hrpp_interface.h"
#include "trace_interface.h"

namespace hrpp {

class VulkanContext;
class ComputePipeline;
class StorageBuffer;

class GpuPredictor {
 public:
  // Throws hrpp::Error when the device lacks 64-bit integer atomics or the table exceeds a
  // storage buffer (naming the table and the limit), or the configuration is invalid.
  GpuPredictor(VulkanContext& ctx, const GpuBvh& bvh, const PredictorConfig& config);
  ~GpuPredictor();
  GpuPredictor(GpuPredictor&&) noexcept;
  GpuPredictor& operator=(GpuPredictor&&) noexcept;
  GpuPredictor(const GpuPredictor&) = delete;
  GpuPredictor& operator=(const GpuPredictor&) = delete;

  const PredictorConfig& config() const;

  // Points the predictor bindings (HRPP_PREDICT_BINDING_FIRST..) of a trace_*_hrpp pipeline at
  // the hit-any or hit-all table. Sizes the request array for `rays` rays per dispatch.
  void bind(ComputePipeline& pipeline, bool any_hit, std::size_t rays);

  // Before a trace call: zeroes the class's counters.
  void begin_trace(bool any_hit);
  // Before recording a predicted trace of the class (host write, outside a command buffer):
  // its use stamps start at `clock`.
  void set_clock(bool any_hit, std::uint32_t clock);
  // Rays one workgroup of a trace_*_hrpp kernel takes: every lane, or one per subgroup in
  // serial mode, times rays_per_invocation.
  std::uint32_t rays_per_workgroup(std::uint32_t rays_per_invocation) const;
  // Deterministic order (config().batch = K > 0): records the predicted trace of rays[0..count)
  // as, per batch of K rays, a trace dispatch (the counters buffer's next_ray and ray_count
  // set to the batch) and an hrpp_insert dispatch that applies its inserts in ray order.
  // Needs the count on the host. `clock`: use stamp of ray 0.
  void record_batches(VkCommandBuffer cmd, ComputePipeline& trace,
                      const gpu::TracePushConstants& pc, StorageBuffer& counters, bool any_hit,
                      std::uint32_t count, std::uint32_t clock);
  // After the submit: the class's counters since begin_trace.
  gpu::PredictorCounters counters(bool any_hit) const;
  // Reads the class's table back and counts what it holds.
  TableOccupancy occupancy(bool any_hit) const;
  // Empties both tables.
  void clear();
  // Turns the counting of full traversals (PredictorConfig::count_baseline) on or off.
  void set_count_baseline(bool on);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace hrpp
