// The benchmark harness's timing of one tracer over one batch: a warm-up on a slice, then
// repeated timed runs over the whole batch, the median reported; and the machine's CPU name,
// which every figure carries.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gpu_types.h"
#include "harness/tracer.h"
#include "harness/validation.h"
#include "hrpp_types.h"
#include "trace/traversal_counters.h"

namespace hrpp {

struct TracerResult {
  TracerKind kind = TracerKind::kCpuReference;
  std::string name;
  std::vector<double> ms;  // per timed run
  double median_ms = 0.0;
  double mrays = 0.0;
  std::size_t hits = 0;
  Validation validation;
  std::optional<TraversalCounters> counters;          // GPU: work per batch
  std::optional<gpu::PredictorCounters> predictor;  // cpu-hrpp, rq-hrpp: the last run's HRPP_PC_*
  std::string timing;                                 // what the ms measure
  bool speculative = false;  // HRPP speculative hit-all: mismatches are wrong predictions
};

// A warm-up on the first 64k rays, then `repeat` timed runs over `rays`; `hits`: the last run's.
// The validation is left for the caller.
TracerResult time_tracer(Tracer& tracer, std::span<const gpu::Ray> rays, QueryKind kind, int repeat,
                         std::vector<gpu::Hit>& hits);

// The CPU's model name (/proc/cpuinfo), or "unknown".
std::string cpu_model();

}  // namespace hrpp
