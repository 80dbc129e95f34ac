#include "hrpp/reference_predictor.h"

#include <algorithm>
#include <array>

#include "hrpp/prediction_node.h"
#include "hrpp/shared_table.h"
#include "hrpp_distance_gate.h"
#include "hrpp_table_set.h"
#include "trace/cpu_traversal.h"
#include "trace/ray_setup.h"
#include "trace_interface.h"

namespace hrpp {
ReferencePredictor::ReferencePredictor(const GpuBvh& bvh, const PredictorConfig& config)
    : bvh_(&bvh), config_(config), leaf_of_prim_(leaf_of_prim(bvh)) {
  for (RayClass c : kRayClasses) {
    params_[c] = make_predictor_params(config, c, bvh.bounds);
    tables_[c] = ReferenceTable(params_[c]);
  }
}

// One class's trace: the stage's steps for one ray at a time (shaders/lib/hrpp_predict.glsl,
// the trace kernel, shaders/hrpp_resolve.comp), counting what the kernels count.
struct ReferencePredictor::Trace {
  // The nodes a queued ray's trace does not enter (HRPP_EMPTY_NODE: none).
  using SkipList = std::array<int, HRPP_SKIP_NODES>;

  const ReferencePredictor& p;
  const QueryKind kind;
  const bool exact;
  const bool skips;                    // fallback skip
  const gpu::PredictorParams& params;  // the class's
  PredictorTraceResult& out;
  std::vector<Insert>& inserts;  // of the current batch, applied after it in ray order
  SharedTable* shared;           // the threads' table (share_tables), else nullptr

  std::uint64_t& counter(int i) { return out.predictor.c[i]; }

  // A traversal from the root with the ray's [tmin, tmax] that does not enter the nodes in
  // `skip`; adds its work to `into`.
  gpu::Hit full_trace(const gpu::Ray& r, TraversalCounters& into,
                      std::span<const int> skip = {}) const {
    if (p.full_trace_) return p.full_trace_(r);
    if (!p.count_work_) return trace_skipping(*p.bvh_, r, kind, skip);
    TraversalCounters f;
    const gpu::Hit h = trace_skipping(*p.bvh_, r, kind, skip, &f);
    f.rays = 0;
    f.hits = 0;
    into += f;
    return h;
  }

  // The entry's nodes in slot order, up to the first empty slot: the closest hit among them
  // (hit-any: the first). With fallback skip, `tested` gets the first HRPP_SKIP_NODES.
  gpu::Hit verify(const gpu::Ray& ray, std::span<const int> slots, SkipList& tested) {
    gpu::Hit predicted = kMiss;
    TraversalCounters v;
    std::size_t tested_count = 0;
    for (const int node : slots) {
      if (node == HRPP_EMPTY_NODE) break;
      gpu::Ray r = ray;
      if (predicted.prim >= 0) r.tmax = predicted.t;
      const bool answered =
          trace_subtree(*p.bvh_, r, node, kind, predicted, p.count_work_ ? &v : nullptr);
      if (skips && tested_count < tested.size()) tested[tested_count++] = node;
      if (answered) break;
    }
    counter(HRPP_PC_VERIFY_INTERIOR) += v.interior_visited;
    counter(HRPP_PC_VERIFY_LEAVES) += v.leaves_visited;
    counter(HRPP_PC_VERIFY_TRIANGLES) += v.triangles_tested;
    out.counters += v;
    ++counter(predicted.prim >= 0 ? HRPP_PC_TRUE_POSITIVES : HRPP_PC_FALSE_POSITIVES);
    return predicted;
  }

  // Probe and verify (hrpp_predict). Returns the predicted hit (prim < 0: none); `nearest`:
  // the entry's nearest-hit word (0: no entry, or none yet).
  gpu::Hit predict(const gpu::Ray& ray, Table& table, std::uint64_t key, std::uint32_t clock,
                   SkipList& tested, std::uint32_t& nearest) {
    ++counter(HRPP_PC_PROBES);
    SharedTable::Nodes copy;
    const std::span<const int> slots =
        shared ? std::span<const int>(copy.data(), shared->lookup(key, clock, copy, nearest))
               : table.lookup(key, clock, nearest);
    if (slots.empty()) {
      ++counter(HRPP_PC_NEGATIVES);
      return kMiss;
    }
    ++counter(HRPP_PC_PREDICTOR_HITS);
    return verify(ray, slots, tested);
  }

  // count_baseline: what HRPP off would visit (not in the trace counters) and whether a
  // speculative answer (`speculative`: accepted as it is) was the closest hit.
  void count_baseline(const gpu::Ray& ray, const gpu::Hit& predicted, bool speculative) {
    TraversalCounters b;  // counted whether or not the work is
    const gpu::Hit truth = trace_skipping(*p.bvh_, ray, kind, {}, &b);
    counter(HRPP_PC_BASELINE_INTERIOR) += b.interior_visited;
    counter(HRPP_PC_BASELINE_LEAVES) += b.leaves_visited;
    counter(HRPP_PC_BASELINE_TRIANGLES) += b.triangles_tested;
    if (speculative && (truth.prim != predicted.prim || truth.t != predicted.t))
      ++counter(HRPP_PC_WRONG_CLOSEST);
  }

  // The answer of a probed ray: the prediction (`speculative`: a hit-all one accepted as it
  // is), or the trace of the queue (a bounded true positive: tmax = the predicted t, the closer
  // of the two, ties to the lower id), not entering the nodes in `skip`. `traced`: the ray was
  // queued (then a hit inserts).
  gpu::Hit answer(const gpu::Ray& ray, const gpu::Hit& predicted, const SkipList& skip,
                  bool speculative, bool& traced) {
    traced = predicted.prim < 0 || (kind == QueryKind::kClosest && !speculative);
    if (!traced) return predicted;
    gpu::Ray r = ray;
    if (predicted.prim >= 0) r.tmax = predicted.t;
    const gpu::Hit best = full_trace(r, out.counters, skip);
    if (predicted.prim >= 0 && (best.prim < 0 || predicted.t < best.t ||
                                (predicted.t == best.t && predicted.prim < best.prim)))
      return predicted;
    return best;
  }

  gpu::Hit trace_ray(const gpu::Ray& ray, Table& table, std::uint32_t clock) {
    if (!setup_ray(ray).valid)  // misses unprobed
      return p.full_trace_ ? kMiss : full_trace(ray, out.counters);
    const std::uint64_t key =
        gpu::hrpp_sm_key(hash_ray(ray.origin, ray.dir, ray.tmax, params.hash), clock,
                         params.sm_tables);
    SkipList tested;
    tested.fill(HRPP_EMPTY_NODE);
    std::uint32_t nearest = 0;
    const gpu::Hit predicted = predict(ray, table, key, clock, tested, nearest);
    const bool hit_all_tp = predicted.prim >= 0 && kind == QueryKind::kClosest && !exact;
    const bool gated = hit_all_tp && gpu::hrpp_gated(predicted.t, nearest, params.gate);
    if (gated) ++counter(HRPP_PC_GATED);
    if (p.config_.count_baseline) count_baseline(ray, predicted, hit_all_tp && !gated);
    bool traced = false;
    const gpu::Hit best = answer(ray, predicted, tested, hit_all_tp && !gated, traced);
    if (traced && best.prim >= 0) {
      ++counter(HRPP_PC_INSERT_REQUESTS);
      const std::uint32_t leaf = p.leaf_of_prim_[static_cast<std::size_t>(best.prim)];
      inserts.push_back(
          {key, prediction_node(*p.bvh_, leaf, params.go_up, params.go_up_size), best.t, clock});
    }
    return best;
  }

  // hrpp_insert: the batch's inserts in ray order.
  void apply_inserts(Table& table) {
    for (const Insert& in : inserts) {
      std::uint64_t& evictions = counter(HRPP_PC_EVICTIONS);
      switch (shared ? shared->insert(in.key, in.node, in.t, in.clock, evictions)
                     : table.insert(in.key, in.node, in.t, in.clock, evictions)) {
        case ReferenceTable::Outcome::kInserted: ++counter(HRPP_PC_INSERTS); break;
        case ReferenceTable::Outcome::kPresent: ++counter(HRPP_PC_INSERT_PRESENT); break;
        case ReferenceTable::Outcome::kDropped: ++counter(HRPP_PC_INSERT_DROPS); break;
      }
    }
    inserts.clear();
  }
};

PredictorTraceResult ReferencePredictor::trace(std::span<const gpu::Ray> rays, RayClass cls) {
  std::vector<gpu::Hit> hits(rays.size());
  PredictorTraceResult out = trace(rays, cls, hits);
  out.hits = std::move(hits);
  return out;
}

PredictorTraceResult ReferencePredictor::trace(std::span<const gpu::Ray> rays, RayClass cls,
                                               std::span<gpu::Hit> hits) {
  PredictorTraceResult out;
  Trace t{*this,
          query_kind(cls),
          config_.mode == PredictorMode::kExact,
          config_.fallback == Fallback::kSkip,
          params_[cls],
          out,
          pending_,
          shared_[cls]};
  pending_.clear();
  Table& table = tables_[cls];
  const std::uint32_t clock = t.shared ? t.shared->draw_clock(static_cast<std::uint32_t>(
                                             rays.size()))
                                       : clocks_[cls];
  const std::size_t batch = std::max<std::size_t>(config_.batch, 1);
  for (std::size_t first = 0; first < rays.size(); first += batch) {
    const std::size_t end = std::min(rays.size(), first + batch);
    for (std::size_t i = first; i < end; ++i) {
      const gpu::Hit best =
          t.trace_ray(rays[i], table, clock + static_cast<std::uint32_t>(i));
      ++out.counters.rays;
      if (best.prim >= 0) ++out.counters.hits;
      hits[i] = t.kind == QueryKind::kAny
                        ? (best.prim >= 0 ? gpu::Hit{0, 0.0f, 0.0f, 0.0f} : kMiss)
                        : best;
    }
    t.apply_inserts(table);
  }
  clocks_[cls] += static_cast<std::uint32_t>(rays.size());
  return out;
}

gpu::Hit ReferencePredictor::trace_one(const gpu::Ray& ray, RayClass c, TraversalCounters& counters,
                                       gpu::PredictorCounters& predictor) {
  gpu::Hit hit;
  const PredictorTraceResult r = trace(std::span(&ray, 1), c, std::span(&hit, 1));
  counters += r.counters;
  predictor += r.predictor;
  return hit;
}

std::uint64_t ReferencePredictor::entries(RayClass c) const { return tables_[c].entries(); }

std::uint64_t ReferencePredictor::stored_nodes(RayClass c) const {
  return tables_[c].stored_nodes();
}

}  // namespace hrpp
