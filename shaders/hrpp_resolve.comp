// hrpp_resolve: the last stage of a predicted trace (hrpp_predict → queue → trace kernel →
// hrpp_resolve), one queue entry per invocation, dispatched indirectly from the queue:
//   - the trace's hit of the queued ray becomes the ray's answer; exact mode or a gated true
//     positive (entry bounded by its predicted t): the closer of the trace's hit and the
//     predicted one that hrpp_predict left in the hit array, ties to the lower id (the
//     predicted triangle's own box may be culled at tmax = its t: the slab test's near
//     distance rounds too);
//   - a probed ray whose answer is a hit inserts the prediction node of the hit under its key:
//     at once (hrpp_table.glsl), or as a request that hrpp_insert.comp applies in ray order
//     (PredictorParams.insert_deferred, the deterministic batches).
// Works for both query kinds: a hit-any answer is the first occluder found (prim >= 0).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require

#include "hrpp_interface.h"

layout(local_size_x = HRPP_RESOLVE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;
layout(push_constant) uniform PushConstants { StagePushConstants pc; };

#include "lib/hrpp_stage.glsl"

HRPP_INSERT_COUNTERS(HRPP_DECLARE_COUNT)

Hit answer_of(QueueEntry e, Hit traced) {
  if ((e.flags & HRPP_QUEUE_BOUNDED) == 0u) return traced;
  const Hit predicted = load_hit(e.ray);
  if (traced.prim < 0 || predicted.t < traced.t ||
      (predicted.t == traced.t && predicted.prim < traced.prim))
    return predicted;
  return traced;
}

void insert(QueueEntry e, Hit answer) {
  ++count_insert_requests;
  const int node = hrpp_node_of_prim(uint(answer.prim));
  if (hrpp.insert_deferred != 0u) {
    hrpp_requests[e.ray] = InsertRequest(e.key_lo, e.key_hi, node, answer.t);
    return;
  }
  const uint64_t key = uint64_t(e.key_lo) | (uint64_t(e.key_hi) << 32);
  const uint outcome =
      hrpp_table_insert(key, node, answer.t, hrpp.clock + e.ray, count_evictions);
  if (outcome == kHrppInserted) ++count_inserts;
  else if (outcome == kHrppPresent) ++count_insert_present;
  else ++count_insert_drops;
}

void main() {
  const uint i = gl_GlobalInvocationID.x;
  uint done = 0u, hit = 0u;
  if (i < queue.queued) {
    const QueueEntry e = load_queue_entry(i);
    const Hit answer = answer_of(e, load_queue_hit(i));
    store_hit(e.ray, answer);
    if (answer.prim >= 0 && (e.flags & HRPP_QUEUE_PROBED) != 0u) insert(e, answer);
    done = 1u;
    hit = answer.prim >= 0 ? 1u : 0u;
  }
  const uint queue_sums[2] = uint[](subgroupAdd(done), subgroupAdd(hit));
  if (subgroupElect()) {
    if (queue_sums[0] != 0u) atomicAdd(queue.resolve_done, queue_sums[0]);
    if (queue_sums[1] != 0u) atomicAdd(queue.queue_hits, queue_sums[1]);
  }
  HRPP_FLUSH_COUNTS(HRPP_INSERT_COUNTERS)
}
