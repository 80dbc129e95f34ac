// A trace kernel made for another stage's ray arrays: the HRPP stage (host/front/gpu_predictor.h)
// asks the tracer it stands in front of for one per query kind, binds it to its queue's rays,
// hits and counters, and dispatches it over the queue. The tracer binds what the kernel reads of
// the scene (the BVH arrays, or the driver's acceleration structure); the bindings below are the
// queue's slots in it.
#pragma once

#include <cstdint>
#include <limits>

#include "vk/compute_pipeline.h"

namespace hrpp {

struct QueueTraceKernel {
  static constexpr std::uint32_t kNoBinding = std::numeric_limits<std::uint32_t>::max();

  ComputePipeline pipeline;
  std::uint32_t rays = kNoBinding;      // a texel view of gpu::Ray
  std::uint32_t hits = kNoBinding;      // a texel view of gpu::Hit
  std::uint32_t counters = kNoBinding;  // gpu::TraceCounters
  std::uint32_t skips = kNoBinding;     // the skip lists: the skipping BVH kernels only
};

}  // namespace hrpp
