// What one trace of a ray class did on the device, read back after its submit: the answer of
// the device tracers (host/gpu/device_tracer.h) and of the HRPP stage in front of them
// (host/front/gpu_predictor.h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "gpu_types.h"
#include "hrpp_types.h"
#include "trace/traversal_counters.h"

namespace hrpp {

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

}  // namespace hrpp
