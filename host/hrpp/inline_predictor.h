// HRPP inline in the CPU traversal, the paper's setting: before a ray's traversal, its probe (the
// hash and one table read), the verification of the predicted nodes and, when they do not hold
// its hit, the fallback and the insert; no stage, queue or dispatch between them. It runs the
// CPU reference predictor's code (host/hrpp/reference_predictor.h) with the work counters
// compiled out, on `threads` threads: chunks of kRayChunk consecutive rays are handed out as
// the CPU reference's are (trace/ray_batches.h), and each thread traces its chunks in order through
// tables of its own (TableSharing::kPerThread, the default: no locks; which thread's tables
// see which chunk varies from run to run) or through one table per class that every thread
// probes and fills (kShared: host/hrpp/shared_table.h, striped locks). With one thread every
// counter and table entry is the reference's.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "bvh/gpu_layout.h"
#include "common/name_table.h"
#include "hrpp/predictor_config.h"
#include "trace/ray_class.h"
#include "hrpp/reference_predictor.h"
#include "hrpp/shared_table.h"

namespace hrpp {

enum class TableSharing : std::uint8_t { kPerThread, kShared };
inline constexpr NameTable<TableSharing, 2> kTableSharingNames = {
    {{TableSharing::kPerThread, "per-thread"}, {TableSharing::kShared, "shared"}}};

class InlinePredictor {
 public:
  // threads: 0 = all the hardware's.
  InlinePredictor(const GpuBvh& bvh, const PredictorConfig& config, int threads,
                  TableSharing sharing = TableSharing::kPerThread);

  // Empties every table (the next trace starts cold).
  void clear();

  // Rays their prediction does not answer go to `f` instead of the CPU traversal
  // (ReferencePredictor::set_full_trace): HRPP in front of Embree. Called from every thread.
  void set_full_trace(ReferencePredictor::FullTrace f);

  // Traces the rays as rays of class `c` through the tables, which keep their contents between
  // calls, into `hits` (one per ray, as the trace kernels write them: any-hit prim 0 occluded,
  // -1 free). Counters: rays and hits; the predictor's summed over the threads.
  PredictorTraceResult trace(std::span<const gpu::Ray> rays, RayClass c, std::span<gpu::Hit> hits);

 private:
  const GpuBvh* bvh_;
  PredictorConfig config_;
  int threads_;
  TableSharing sharing_;
  std::vector<ReferencePredictor> tables_;  // one predictor, with its tables, per thread
  PerClass<std::unique_ptr<SharedTable>> shared_;  // kShared: the threads' tables
  ReferencePredictor::FullTrace full_trace_;
};

}  // namespace hrpp
