#include "hrpp/reference_predictor.h"

#include <algorithm>

#include "hrpp/prediction_node.h"
#include "trace/cpu_traversal.h"
#include "trace/ray_setup.h"

namespace hrpp {
namespace {

struct Insert {
  std::uint64_t key;
  int node;
};

}  // namespace

ReferencePredictor::ReferencePredictor(const GpuBvh& bvh, const PredictorConfig& config)
    : bvh_(&bvh),
      config_(config),
      params_(make_predictor_params(config, bvh.bounds)),
      leaf_of_prim_(leaf_of_prim(bvh)) {}

PredictorTraceResult ReferencePredictor::trace(std::span<const gpu::Ray> rays, RayClass cls) {
  const bool any_hit = is_any_hit(cls);
  PredictorTraceResult out;
  out.hits.resize(rays.size());
  auto& pc = out.predictor.c;
  TraversalCounters& c = out.counters;
  Table& table = tables_[cls];
  const bool exact = config_.mode == PredictorMode::kExact;
  const std::size_t batch = std::max<std::size_t>(config_.batch, 1);

  // A traversal from the root with the ray's [tmin, tmax]; adds its work to `into`.
  const auto full_trace = [&](const gpu::Ray& r, TraversalCounters& into) {
    TraversalCounters f;
    const gpu::Hit h = any_hit ? trace_any_hit(*bvh_, r, &f) : trace_closest(*bvh_, r, &f);
    f.rays = 0;
    f.hits = 0;
    into += f;
    return h;
  };

  for (std::size_t first = 0; first < rays.size(); first += batch) {
    const std::size_t end = std::min(rays.size(), first + batch);
    std::vector<Insert> inserts;  // applied after the batch, in ray order
    for (std::size_t i = first; i < end; ++i) {
      const gpu::Ray& ray = rays[i];
      gpu::Hit best = kMiss;
      if (!setup_ray(ray).valid) {  // misses without probing
        best = full_trace(ray, c);
      } else {
        ++pc[HRPP_PC_PROBES];
        const std::uint64_t key = hash_ray(ray.origin, ray.dir, params_.hash);
        const auto entry = table.find(key);
        gpu::Hit predicted = kMiss;
        if (entry == table.end()) {
          ++pc[HRPP_PC_NEGATIVES];
        } else {
          ++pc[HRPP_PC_PREDICTOR_HITS];
          TraversalCounters v;
          for (const int node : entry->second) {
            gpu::Ray r = ray;
            if (predicted.prim >= 0) r.tmax = predicted.t;
            if (trace_subtree(*bvh_, r, node, any_hit, predicted, &v)) break;
          }
          pc[HRPP_PC_VERIFY_INTERIOR] += v.interior_visited;
          pc[HRPP_PC_VERIFY_LEAVES] += v.leaves_visited;
          pc[HRPP_PC_VERIFY_TRIANGLES] += v.triangles_tested;
          c += v;
          ++pc[predicted.prim >= 0 ? HRPP_PC_TRUE_POSITIVES : HRPP_PC_FALSE_POSITIVES];
        }
        bool traced = true;  // a traversal from the root ran (and may insert)
        if (predicted.prim < 0) {  // negative or false positive: full traversal
          TraversalCounters f;
          best = full_trace(ray, f);
          c += f;
          if (config_.count_baseline) pc[HRPP_PC_BASELINE_INTERIOR] += f.interior_visited;
        } else {
          if (config_.count_baseline) {  // what HRPP off would have visited (not in c)
            TraversalCounters b;
            const gpu::Hit truth = full_trace(ray, b);
            pc[HRPP_PC_BASELINE_INTERIOR] += b.interior_visited;
            if (!any_hit && !exact && (truth.prim != predicted.prim || truth.t != predicted.t))
              ++pc[HRPP_PC_WRONG_CLOSEST];
          }
          if (any_hit || !exact) {
            best = predicted;
            traced = false;
          } else {  // exact: the predicted t bounds a full traversal
            gpu::Ray r = ray;
            r.tmax = predicted.t;
            best = full_trace(r, c);
            // The predicted triangle's own box may be culled at tmax = its t (the slab test's
            // near distance rounds too): the closer of the two, ties to the lower id.
            if (best.prim < 0 || predicted.t < best.t ||
                (predicted.t == best.t && predicted.prim < best.prim))
              best = predicted;
          }
        }
        if (traced && best.prim >= 0) {
          ++pc[HRPP_PC_INSERT_REQUESTS];
          const std::uint32_t leaf = leaf_of_prim_[static_cast<std::size_t>(best.prim)];
          inserts.push_back({key, prediction_node(*bvh_, leaf, config_.go_up)});
        }
      }
      ++c.rays;
      if (best.prim >= 0) ++c.hits;
      out.hits[i] = any_hit ? (best.prim >= 0 ? gpu::Hit{0, 0.0f, 0.0f, 0.0f} : kMiss) : best;
    }
    for (const Insert& in : inserts) {
      std::vector<int>& nodes = table[in.key];
      if (std::find(nodes.begin(), nodes.end(), in.node) != nodes.end()) {
        ++pc[HRPP_PC_INSERT_PRESENT];
      } else {
        nodes.push_back(in.node);
        ++pc[HRPP_PC_INSERTS];
      }
    }
  }
  return out;
}

std::uint64_t ReferencePredictor::entries(RayClass c) const {
  return tables_[c].size();
}

std::uint64_t ReferencePredictor::stored_nodes(RayClass c) const {
  std::uint64_t n = 0;
  for (const auto& [key, nodes] : tables_[c]) n += nodes.size();
  return n;
}

}  // namespace hrpp
