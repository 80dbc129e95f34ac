// Body of HRPP's predict kernels: hrpp_predict.comp (hit-all rays, HRPP_ANY_HIT 0) and
// hrpp_predict_any.comp (hit-any, HRPP_ANY_HIT 1). The first stage of a predicted trace:
//   hrpp_predict → queue → trace kernel (the one HRPP off runs) → hrpp_resolve.
// Per ray of the class (the CPU reference predictor, host/hrpp/reference_predictor.h, has the
// same semantics and counts the same things):
//   - a valid ray hashes (hrpp_hash.glsl) and probes its class's table (hrpp_table.glsl);
//     invalid rays are queued without probing (the trace answers them: a miss);
//   - predictor hit: the ray is tested against the entry's nodes in slot order (leaf: its
//     triangles; interior: its subtree), hit-all keeping the closest hit, hit-any stopping at
//     the first. A hit is a true positive: hit-any and speculative hit-all write it as the
//     ray's answer and are done; exact hit-all, and speculative hit-all that the distance gate
//     stops (hrpp_distance_gate.h), write it and queue the ray with tmax = its t (hrpp_resolve
//     keeps the closer of the two: the answer of HRPP off). No hit: false positive, queued. No
//     entry: negative, queued;
//   - with the skip list on (kSkipList, fallback skip) a queued ray also gets the first
//     HRPP_SKIP_NODES nodes it tested, which the queue's trace (trace_*_skipping) does not
//     enter: nothing in them answers the ray before its queued tmax;
//   - queued rays are compacted: one atomicAdd per subgroup (ballot), and the queue's
//     indirect dispatch arguments are raised with one atomicMax per subgroup.
// Persistent invocations and the completion proof are those of shaders/lib/trace_kernel.glsl.
#ifndef HRPP_PREDICT_GLSL
#define HRPP_PREDICT_GLSL

#include "hrpp_interface.h"

layout(local_size_x = HRPP_TRACE_WORKGROUP_SIZE, local_size_x_id = HRPP_SPEC_PREDICT_WORKGROUP,
       local_size_y = 1, local_size_z = 1) in;
layout(push_constant) uniform PushConstants { StagePushConstants pc; };
layout(constant_id = HRPP_SPEC_VERIFY_INTERIOR) const bool kVerifyInterior = true;
layout(constant_id = HRPP_SPEC_COUNT_BASELINE) const bool kCountBaseline = true;
layout(constant_id = HRPP_SPEC_SKIP_LIST) const bool kSkipList = false;

#include "hrpp_stage.glsl"
#include "hrpp_hash.glsl"
#include "traversal.glsl"

// Per-invocation predictor counts, summed per subgroup at the end (flush_counters).
HRPP_PREDICT_COUNTERS(HRPP_DECLARE_COUNT)

// A traversal from the root counted apart (count_baseline): what HRPP off would visit.
Hit baseline_traversal(RaySetup r) {
  const uint i0 = g_interior, l0 = g_leaves, t0 = g_triangles;
  Hit truth = Hit(-1, 0.0, 0.0, 0.0);
  traverse_from(r, 0, truth);
  count_baseline_interior += g_interior - i0;
  count_baseline_leaves += g_leaves - l0;
  count_baseline_triangles += g_triangles - t0;
  g_interior = i0;
  g_leaves = l0;
  g_triangles = t0;
  return truth;
}

// Tests the ray against the nodes of table entry `entry`; returns the closest (hit-any: the
// first) hit among them. `finished` turns false when a traversal did not reach its end; `tested`
// gets the first HRPP_SKIP_NODES nodes tested (kSentinel: none).
Hit verify_entry(RaySetup r, int entry, inout bool finished, inout ivec4 tested) {
  Hit predicted = Hit(-1, 0.0, 0.0, 0.0);
  uint tested_count = 0u;
  const uint first = uint(entry) * hrpp.nodes;
  float tmax = r.tmax;
  bool done = false;  // hit-any answered (no break out of the loop: see hrpp_table.glsl)
  for (uint s = 0u; s < hrpp.nodes && !done; ++s) {
    const int node = int(hrpp_fetch_slot(first + s));
    if (node == HRPP_EMPTY_NODE) {
      done = true;
    } else if (node < 0 || kVerifyInterior) {
      if (node < 0) {
        done = test_leaf(r, node, predicted, tmax);
      } else {
        RaySetup sub = r;
        sub.tmax = tmax;
        finished = traverse_from(sub, node, predicted) && finished;
        if (predicted.prim >= 0) tmax = predicted.t;
        done = HRPP_ANY_HIT != 0 && predicted.prim >= 0;
      }
      if (kSkipList && tested_count < HRPP_SKIP_NODES) tested[tested_count++] = node;
    }
  }
  return predicted;
}

// Probes the table for ray `index` (set up as r) and verifies the prediction. Returns the
// predicted hit (prim < 0: none); `tested`: the nodes tested (verify_entry); `nearest`: the
// entry's nearest-hit word with the distance gate on (else 0).
Hit predict(uint index, RaySetup r, uint64_t key, inout bool finished, inout ivec4 tested,
            out uint nearest) {
  ++count_probes;
  nearest = 0u;
  const int entry = hrpp_table_lookup(key, hrpp.clock + index);
  if (entry < 0) {
    ++count_negatives;
    return Hit(-1, 0.0, 0.0, 0.0);
  }
  ++count_predictor_hits;
  if (hrpp.gate > 0.0) nearest = hrpp_stamps[hrpp_nearest_index(uint(entry))];
  const uint i0 = g_interior, l0 = g_leaves, t0 = g_triangles;
  const Hit predicted = verify_entry(r, entry, finished, tested);
  count_verify_interior += g_interior - i0;
  count_verify_leaves += g_leaves - l0;
  count_verify_triangles += g_triangles - t0;
  if (predicted.prim >= 0) ++count_true_positives;
  else ++count_false_positives;
  return predicted;
}

// Appends the rays whose `wanted` is true to the queue, with their skip lists (every lane of the
// subgroup calls this).
void enqueue(bool wanted, Ray ray, QueueEntry entry, ivec4 skips) {
  const uvec4 lanes = subgroupBallot(wanted);
  const uint n = subgroupBallotBitCount(lanes);
  uint base = 0u;
  if (subgroupElect() && n > 0u) {
    base = atomicAdd(queue.queued, n);
    const uint end = base + n;
    atomicMax(queue.trace_groups[0], (end + pc.trace_group_rays - 1u) / pc.trace_group_rays);
    atomicMax(queue.resolve_groups[0],
              (end + HRPP_RESOLVE_WORKGROUP_SIZE - 1u) / HRPP_RESOLVE_WORKGROUP_SIZE);
  }
  base = subgroupBroadcastFirst(base);
  if (wanted) {
    const uint slot = base + subgroupBallotExclusiveBitCount(lanes);
    store_queue_ray(slot, ray);
    store_queue_entry(slot, entry);
    if (kSkipList) store_queue_skips(slot, skips);
  }
}

// Predicts ray `index`: writes its answer (resolved) or queues it. Returns false when a loop
// limiter cut it short (then it is neither).
bool predict_ray(uint index, bool in_range, out bool resolved) {
  resolved = false;
  Ray ray = Ray(vec3(0.0), 0.0, vec3(0.0), 0.0);
  QueueEntry entry = QueueEntry(index, 0u, 0u, 0u);
  bool finished = true;
  ivec4 tested = ivec4(kSentinel);
  if (in_range) {
    if (hrpp.insert_deferred != 0u)
      hrpp_requests[index] = InsertRequest(0u, 0u, HRPP_EMPTY_NODE, 0.0);
    ray = load_ray(index);
    const RaySetup r = setup_ray(ray);
    if (r.valid) {
      const uint64_t key = hrpp_sm_key(hrpp_hash_ray(ray.origin, ray.dir, ray.tmax, hrpp.hash),
                                       hrpp.clock + index, hrpp.sm_tables);
      entry = QueueEntry(index, HRPP_QUEUE_PROBED, uint(key), uint(key >> 32));
      uint nearest;
      const Hit predicted = predict(index, r, key, finished, tested, nearest);
      // A speculative answer: a true positive of a hit-all ray that the gate lets through.
      const bool speculative = HRPP_ANY_HIT == 0 && hrpp.mode == HRPP_MODE_SPECULATIVE &&
                               predicted.prim >= 0;
      const bool gated = speculative && hrpp_gated(predicted.t, nearest, hrpp.gate);
      if (gated) ++count_gated;
      if (kCountBaseline && hrpp.count_baseline != 0u) {
        const Hit truth = baseline_traversal(r);
        if (speculative && !gated && (truth.prim != predicted.prim || truth.t != predicted.t))
          ++count_wrong_closest;
      }
      if (predicted.prim >= 0) {
        store_hit(index, predicted);
        resolved = HRPP_ANY_HIT != 0 || (speculative && !gated);
        entry.flags |= HRPP_QUEUE_BOUNDED;
        ray.tmax = predicted.t;
      }
    }
    finished = loop_budget_left() && finished;
  }
  enqueue(in_range && finished && !resolved, ray, entry, tested);
  return finished;
}

// Adds this subgroup's predictor counts to the class's counters; call once, at the end of main.
void flush_counters() { HRPP_FLUSH_COUNTS(HRPP_PREDICT_COUNTERS) }

// The rays of this dispatch (shaders/shared/hrpp_passes.h): all of the queue's ray_count, or
// one pass of the pilot schedule (PredictorConfig::pilot: first the rays whose index is a
// multiple of K, so that the rest find their entries), or the adaptive predictor's sample.
uint pass_ray_count(uint total) { return hrpp_pass_ray_count(total, pc.pilot_pass, pc.pilot_stride); }

uint ray_index(uint j) { return hrpp_pass_ray_index(j, pc.pilot_pass, pc.pilot_stride); }

void main() {
  if (hrpp.serial != 0u && gl_SubgroupInvocationID != 0u) return;  // one ray per subgroup
  const uint count = pass_ray_count(queue.ray_count);
  // Workgroups past the pass's rays leave before their atomics: the second pass of the pilot
  // schedule is dispatched with the trace's own arguments (a workgroup per trace_group_rays of
  // every ray), and HRPP_PASS_NONE has no ray at all.
  if (gl_WorkGroupID.x * pc.trace_group_rays >= count) return;
  uint resolved_count = 0u, aborted = 0u;
  // The workgroup's trace_group_rays rays over its working lanes (serial: one per subgroup).
  const uint lanes = hrpp.serial != 0u ? gl_NumSubgroups : gl_WorkGroupSize.x;
  const uint rays_per_lane = (pc.trace_group_rays + lanes - 1u) / lanes;
  for (uint k = 0u; k < rays_per_lane; ++k) {
    // One atomicAdd per subgroup for all its active lanes (any subgroup size).
    const uvec4 lanes = subgroupBallot(true);
    uint base = 0u;
    if (subgroupElect()) base = atomicAdd(queue.next_ray, subgroupBallotBitCount(lanes));
    base = subgroupBroadcastFirst(base);
    if (base >= count) break;  // uniform across the subgroup
    const uint j = base + subgroupBallotExclusiveBitCount(lanes);
    const bool in_range = j < count;
    bool resolved;
    const bool finished = predict_ray(ray_index(j), in_range, resolved);
    if (in_range && !finished) ++aborted;
    if (in_range && finished && resolved) ++resolved_count;
  }
  const uint resolved_sum = subgroupAdd(resolved_count);
  const uint aborted_sum = subgroupAdd(aborted);
  if (subgroupElect()) {
    if (resolved_sum != 0u) atomicAdd(queue.resolved, resolved_sum);
    if (aborted_sum != 0u) atomicAdd(queue.aborted, aborted_sum);
  }
  flush_counters();
}

#endif  // HRPP_PREDICT_GLSL
