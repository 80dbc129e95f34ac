// HRPP in the trace kernels (trace_closest_hrpp.comp, trace_any_hrpp.comp): probe before
// traversal. Included by shaders/lib/trace_kernel.glsl when HRPP_PREDICT is 1, after its
// traverse_from() and test_leaf(); the CPU reference predictor (host/hrpp/reference_predictor.h)
// has the same semantics and counts the same things:
//   - a valid ray hashes (hrpp_hash.glsl) and probes the table (hrpp_table.glsl); invalid rays
//     are traced (they miss) without probing;
//   - predictor hit: the ray is tested against the entry's nodes in slot order (leaf: its
//     triangles; interior: its subtree), hit-all keeping the closest hit, hit-any stopping at
//     the first. A hit is a true positive: hit-any and speculative hit-all take it; exact
//     hit-all traverses from the root with tmax = its t (the answer equals HRPP off). No hit:
//     false positive, full traversal. No entry: negative, full traversal;
//   - after a traversal from the root that hit, the prediction node of the hit (go-up applied
//     on the host: node_of_prim) is inserted under the key: at once, or as a request that
//     hrpp_insert.comp applies after the batch (PredictorParams.insert_deferred).
#ifndef HRPP_PREDICT_GLSL
#define HRPP_PREDICT_GLSL

#define HRPP_TABLE_BASE HRPP_PREDICT_BINDING_FIRST
#include "hrpp_hash.glsl"
#include "hrpp_table.glsl"

layout(std430, set = 0, binding = HRPP_PREDICT_BINDING_FIRST + HRPP_PREDICT_NODE_OF_PRIM) readonly
    restrict buffer HrppNodeOfPrimBuffer {
  int hrpp_node_of_prim[];
};

// Per-invocation predictor counts, summed per subgroup at the end (hrpp_flush_counters).
uint h_probes = 0u, h_hits = 0u, h_tp = 0u, h_fp = 0u, h_neg = 0u;
uint h_verify_interior = 0u, h_verify_leaves = 0u, h_verify_triangles = 0u;
uint h_baseline = 0u, h_wrong = 0u;
uint h_requests = 0u, h_inserted = 0u, h_present = 0u, h_dropped = 0u, h_evictions = 0u;

// A traversal from the root counted apart (count_baseline): what HRPP off would visit. Its work
// is taken back out of the trace counters.
Hit hrpp_baseline(RaySetup r) {
  const uint i0 = g_interior, l0 = g_leaves, t0 = g_triangles;
  Hit truth = Hit(-1, 0.0, 0.0, 0.0);
  traverse_from(r, 0, truth);
  h_baseline += g_interior - i0;
  g_interior = i0;
  g_leaves = l0;
  g_triangles = t0;
  return truth;
}

void hrpp_insert(uint index, uint64_t key, Hit found) {
  ++h_requests;
  const int node = hrpp_node_of_prim[found.prim];
  if (hrpp.insert_deferred != 0u) {
    hrpp_requests[index] = InsertRequest(uint(key), uint(key >> 32), node, 0u);
    return;
  }
  const uint outcome = hrpp_table_insert(key, node, hrpp.clock + index, h_evictions);
  if (outcome == kHrppInserted) ++h_inserted;
  else if (outcome == kHrppPresent) ++h_present;
  else ++h_dropped;
}

// Traces ray `index` (set up as r) with prediction into `best`. Returns false when a traversal
// did not reach its end (loop limiter).
bool hrpp_trace(RaySetup r, uint index, inout Hit best) {
  if (hrpp.insert_deferred != 0u)
    hrpp_requests[index] = InsertRequest(0u, 0u, HRPP_EMPTY_NODE, 0u);
  if (!r.valid) return traverse_from(r, 0, best);
  ++h_probes;
  const Ray ray = load_ray(index);
  const uint64_t key = hrpp_hash_ray(ray.origin, ray.dir, hrpp.hash);
  const int entry = hrpp_table_lookup(key, hrpp.clock + index);
  Hit predicted = Hit(-1, 0.0, 0.0, 0.0);
  bool finished = true;
  if (entry < 0) {
    ++h_neg;
  } else {
    ++h_hits;
    const uint i0 = g_interior, l0 = g_leaves, t0 = g_triangles;
    const uint first = uint(entry) * hrpp.nodes;
    float tmax = r.tmax;
    for (uint s = 0u; s < hrpp.nodes; ++s) {
      const int node = int(hrpp_slots[first + s]);
      if (node == HRPP_EMPTY_NODE) break;
      if (node < 0) {
        if (test_leaf(r, node, predicted, tmax)) break;  // any-hit answered
      } else {
        RaySetup sub = r;
        sub.tmax = tmax;
        finished = traverse_from(sub, node, predicted) && finished;
        if (predicted.prim >= 0) {
          tmax = predicted.t;
#if HRPP_ANY_HIT
          break;
#endif
        }
      }
    }
    h_verify_interior += g_interior - i0;
    h_verify_leaves += g_leaves - l0;
    h_verify_triangles += g_triangles - t0;
    if (predicted.prim >= 0) ++h_tp;
    else ++h_fp;
  }

  bool traced = true;  // a traversal from the root ran (and may insert)
  if (predicted.prim < 0) {
    const uint i0 = g_interior;
    finished = traverse_from(r, 0, best) && finished;
    if (hrpp.count_baseline != 0u) h_baseline += g_interior - i0;
  } else {
    if (hrpp.count_baseline != 0u) {
      const Hit truth = hrpp_baseline(r);
#if !HRPP_ANY_HIT
      if (hrpp.mode == HRPP_MODE_SPECULATIVE && (truth.prim != predicted.prim || truth.t != predicted.t))
        ++h_wrong;
#endif
    }
#if HRPP_ANY_HIT
    best = predicted;
    traced = false;
#else
    if (hrpp.mode == HRPP_MODE_SPECULATIVE) {
      best = predicted;
      traced = false;
    } else {
      RaySetup bounded = r;
      bounded.tmax = predicted.t;
      finished = traverse_from(bounded, 0, best) && finished;
      // The predicted triangle's own box may be culled at tmax = its t (the slab test's near
      // distance rounds too): the closer of the two, ties to the lower id.
      if (best.prim < 0 || predicted.t < best.t ||
          (predicted.t == best.t && predicted.prim < best.prim))
        best = predicted;
    }
#endif
  }
  if (traced && best.prim >= 0) hrpp_insert(index, key, best);
#if HRPP_ANY_HIT
  if (best.prim >= 0) best = Hit(0, 0.0, 0.0, 0.0);  // the any-hit record: occluded
#endif
  return finished;
}

// Adds this subgroup's predictor counts to the counters buffer; call once, at the end of main.
void hrpp_flush_counters() {
  const uint sums[HRPP_PC_COUNT] = uint[](
      subgroupAdd(h_probes), subgroupAdd(h_hits), subgroupAdd(h_tp), subgroupAdd(h_fp),
      subgroupAdd(h_neg), subgroupAdd(h_verify_interior), subgroupAdd(h_verify_leaves),
      subgroupAdd(h_verify_triangles), subgroupAdd(h_baseline), subgroupAdd(h_wrong),
      subgroupAdd(h_requests), subgroupAdd(h_inserted), subgroupAdd(h_present),
      subgroupAdd(h_dropped), subgroupAdd(h_evictions), 0u);
  // No loop (the loop limiter may have fired): one statement per counter.
  if (subgroupElect()) {
    hrpp_add_counter(HRPP_PC_PROBES, sums[HRPP_PC_PROBES]);
    hrpp_add_counter(HRPP_PC_PREDICTOR_HITS, sums[HRPP_PC_PREDICTOR_HITS]);
    hrpp_add_counter(HRPP_PC_TRUE_POSITIVES, sums[HRPP_PC_TRUE_POSITIVES]);
    hrpp_add_counter(HRPP_PC_FALSE_POSITIVES, sums[HRPP_PC_FALSE_POSITIVES]);
    hrpp_add_counter(HRPP_PC_NEGATIVES, sums[HRPP_PC_NEGATIVES]);
    hrpp_add_counter(HRPP_PC_VERIFY_INTERIOR, sums[HRPP_PC_VERIFY_INTERIOR]);
    hrpp_add_counter(HRPP_PC_VERIFY_LEAVES, sums[HRPP_PC_VERIFY_LEAVES]);
    hrpp_add_counter(HRPP_PC_VERIFY_TRIANGLES, sums[HRPP_PC_VERIFY_TRIANGLES]);
    hrpp_add_counter(HRPP_PC_BASELINE_INTERIOR, sums[HRPP_PC_BASELINE_INTERIOR]);
    hrpp_add_counter(HRPP_PC_WRONG_CLOSEST, sums[HRPP_PC_WRONG_CLOSEST]);
    hrpp_add_counter(HRPP_PC_INSERT_REQUESTS, sums[HRPP_PC_INSERT_REQUESTS]);
    hrpp_add_counter(HRPP_PC_INSERTS, sums[HRPP_PC_INSERTS]);
    hrpp_add_counter(HRPP_PC_INSERT_PRESENT, sums[HRPP_PC_INSERT_PRESENT]);
    hrpp_add_counter(HRPP_PC_INSERT_DROPS, sums[HRPP_PC_INSERT_DROPS]);
    hrpp_add_counter(HRPP_PC_EVICTIONS, sums[HRPP_PC_EVICTIONS]);
  }
}

#endif  // HRPP_PREDICT_GLSL
