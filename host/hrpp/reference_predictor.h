// The CPU reference predictor: the class's predictor table (host/hrpp/reference_table.h, the
// GPU table's sets × ways × nodes and replacement policy) over the CPU reference traversal
// (host/trace/cpu_traversal.h), with the kernels' semantics and counters
// (shaders/lib/hrpp_predict.glsl):
//   - a valid ray is hashed and probes its class's table (camera, bounce, shadow); invalid rays are
//     traced (they miss) without probing;
//   - predictor hit: the ray is tested against the entry's nodes in list order (leaf: its
//     triangles; interior: its subtree), hit-all keeping the closest hit (tmax shrinking across
//     nodes), hit-any stopping at the first hit. A hit is a true positive: hit-any and
//     speculative hit-all take it; exact hit-all, and speculative hit-all that the distance
//     gate stops (shaders/shared/hrpp_distance_gate.h), trace from the root with tmax = its t and
//     keep the closer of that answer and the predicted hit (ties: lower id). No hit:
//     false positive, full traversal. No entry: negative, full traversal. With
//     fallback skip (PredictorConfig::fallback) these traversals do not enter the first
//     HRPP_SKIP_NODES nodes the verification tested;
//   - after every full traversal that hit, the prediction node (host/hrpp/prediction_node.h)
//     of the hit is inserted under the ray's key, at the ray's use stamp (the class's rays
//     traced so far + its index), evicting or dropping as the table's policy says;
//   - order: PredictorConfig::batch (K = 0 is taken as 1: every ray sees all earlier rays).
// In the GPU's deterministic configuration (batches, one ray per subgroup) every counter,
// evictions and drops included, and every table entry are the GPU's.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "bvh/gpu_layout.h"
#include "hrpp/predictor_config.h"
#include "hrpp/reference_table.h"
#include "trace/ray_class.h"
#include "trace/traversal_counters.h"

namespace hrpp {

class SharedTable;

struct PredictorTraceResult {
  std::vector<gpu::Hit> hits;          // as the trace kernels write them (any-hit: 0 / -1)
  TraversalCounters counters;          // all work, verification included
  gpu::PredictorCounters predictor{};  // HRPP_PC_*
};

class ReferencePredictor {
 public:
  ReferencePredictor(const GpuBvh& bvh, const PredictorConfig& config);

  // Traces rays of one class through its table; the table keeps its contents between calls.
  PredictorTraceResult trace(std::span<const gpu::Ray> rays, RayClass c);
  // The same, the hits written into `hits` (one per ray; PredictorTraceResult::hits left empty).
  PredictorTraceResult trace(std::span<const gpu::Ray> rays, RayClass c, std::span<gpu::Hit> hits);

  // One ray, its inserts applied after it (as batch 0): its work added to `counters`, its
  // predictor counters to `predictor`. The CPU renderer's per-ray trace (host/cpu_render/).
  gpu::Hit trace_one(const gpu::Ray& ray, RayClass c, TraversalCounters& counters,
                     gpu::PredictorCounters& predictor);

  // The traversal of a ray its prediction did not answer, in place of the CPU traversal: an
  // outside tracer (Embree in `hrpp bench`) giving the closest hit within the ray's [tmin, tmax]
  // for either query kind (a hit-any insert needs the occluder's triangle). With one, the
  // fallback is root (an outside tracer cannot skip the verified nodes), its work is not
  // counted, and an invalid ray misses without a call.
  using FullTrace = std::function<gpu::Hit(const gpu::Ray&)>;
  void set_full_trace(FullTrace f) { full_trace_ = std::move(f); }

  // Probe and insert into these tables (one per class; nullptr: the predictor's own) instead:
  // tables that several predictors, one per thread, share (host/hrpp/shared_table.h).
  void share_tables(const PerClass<SharedTable*>& tables) { shared_ = tables; }

  // Off: the traversals count no work (PredictorTraceResult::counters keeps rays and hits, the
  // predictor's counters all but the verification's), and compile without their increments:
  // the inline predictor's timed path (host/hrpp/inline_predictor.h). On by default.
  void count_work(bool on) { count_work_ = on; }

  // Keys in the class's table and node references stored under them.
  std::uint64_t entries(RayClass c) const;
  std::uint64_t stored_nodes(RayClass c) const;

 private:
  using Table = ReferenceTable;
  struct Insert {
    std::uint64_t key;
    int node;
    float t;              // the hit's (the distance gate's nearest hit)
    std::uint32_t clock;  // the ray's use stamp
  };
  struct Trace;

  const GpuBvh* bvh_;
  PredictorConfig config_;
  PerClass<gpu::PredictorParams> params_;  // each class's key and go-up level
  std::vector<std::uint32_t> leaf_of_prim_;
  PerClass<Table> tables_;
  PerClass<std::uint32_t> clocks_{};  // rays of the class traced so far (the GPU's clock)
  bool count_work_ = true;
  FullTrace full_trace_;  // empty: the CPU traversal
  PerClass<SharedTable*> shared_{};
  std::vector<Insert> pending_;  // the current batch's inserts (kept: no allocation per ray)
};

}  // namespace hrpp
