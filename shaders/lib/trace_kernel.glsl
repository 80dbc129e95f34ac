// Body of the trace kernels: trace_closest.comp (HRPP_ANY_HIT 0) and trace_any.comp
// (HRPP_ANY_HIT 1), which HRPP off runs on a class's rays and HRPP on runs on the queue of rays
// its prediction did not answer (shaders/hrpp_predict.comp). No predictor code here: the
// traversal is shaders/lib/traversal.glsl.
//
// Persistent invocations: one lane per subgroup fetches the next rays with atomicAdd on a global
// cursor, but at most pc.rays_per_invocation per invocation, because lavapipe's loop limiter
// (docs/DEVICES.md, "Lavapipe") silently ends every loop once a subgroup has run
// 65,535 loop iterations in total. Every ray proves it finished: its traversal loop must end at
// the sentinel and a canary loop with a bound unknown to the compiler (pc.canary_iterations)
// must still run in full. Rays that pass count in HRPP_COUNTER_RAYS; the others in
// counters.aborted; the host compares.
//
// HRPP_TRACE_INDEXED 1 (trace_*_indexed.comp): position j of the dispatch traces the ray whose
// index is entry j of a ray index list (HRPP_TRACE_BINDING_RAY_INDICES) and writes its hit at
// that index, so a reordering (host/gpu/ray_sorter.h) moves no ray and no hit. Without it
// (0, the default) position j is ray j.
//
// HRPP_TRACE_SKIPPING 1 (trace_*_skipping.comp, HRPP's queue with fallback skip):
// position j also reads entry j of a skip list (HRPP_TRACE_BINDING_SKIP_NODES), the nodes its
// prediction tested without an answer, and the traversal does not enter them (traversal.glsl).
#ifndef HRPP_TRACE_KERNEL_GLSL
#define HRPP_TRACE_KERNEL_GLSL

#include "trace_interface.h"

#ifndef HRPP_TRACE_INDEXED
#define HRPP_TRACE_INDEXED 0
#endif

layout(local_size_x = HRPP_TRACE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

// The hit array as a storage texel buffer: one vec4 store per lane (a Hit is one texel), where a
// storage-buffer store costs one per 32-bit word on lavapipe.
layout(set = 0, binding = HRPP_TRACE_BINDING_HITS, rgba32ui) uniform writeonly restrict
    uimageBuffer hit_texels;
#define HRPP_COUNTERS_BINDING HRPP_TRACE_BINDING_COUNTERS
#include "trace_counters.glsl"
layout(push_constant) uniform PushConstants { TracePushConstants pc; };

#include "traversal.glsl"

#if HRPP_TRACE_INDEXED
layout(set = 0, binding = HRPP_TRACE_BINDING_RAY_INDICES) uniform utextureBuffer ray_index_texels;
// The ray traced at position `slot`: entry `slot` of the list, 4 entries per texel.
uint ray_at(uint slot) { return texelFetch(ray_index_texels, int(slot >> 2u))[slot & 3u]; }
#else
uint ray_at(uint slot) { return slot; }
#endif

#if HRPP_TRACE_SKIPPING
layout(set = 0, binding = HRPP_TRACE_BINDING_SKIP_NODES) uniform utextureBuffer skip_texels;
// The node the traversal of position `slot` starts at: the root, unless the root is skipped.
int start_node(uint slot) {
  g_skip = ivec4(texelFetch(skip_texels, int(slot)));
  return skipped(0) ? kSentinel : 0;
}
#else
int start_node(uint slot) { return 0; }
#endif

void main() {
  if (pc.serial != 0u && gl_SubgroupInvocationID != 0u) return;  // one ray per subgroup
  uint done = 0u, hit_count = 0u, aborted = 0u;
  for (uint k = 0u; k < pc.rays_per_invocation; ++k) {
    bool more;
    const uint slot = fetch_position(more);
    if (!more) break;  // uniform across the subgroup
    if (slot >= counters.ray_count) continue;

    const uint index = ray_at(slot);
    const RaySetup r = setup_ray(load_ray(index));
    Hit best = Hit(-1, 0.0, 0.0, 0.0);
    const bool finished = traverse_from(r, start_node(slot), best);
    if (loop_budget_left() && finished) {
      imageStore(hit_texels, int(index), uvec4(uint(best.prim), floatBitsToUint(best.t),
                                               floatBitsToUint(best.u), floatBitsToUint(best.v)));
      ++done;
      if (best.prim >= 0) ++hit_count;
    } else {
      ++aborted;
    }
  }

  const uint sums[HRPP_COUNTER_COUNT] = uint[](subgroupAdd(done), subgroupAdd(g_interior),
                                               subgroupAdd(g_leaves), subgroupAdd(g_triangles),
                                               subgroupAdd(hit_count),
                                               kCountSteps ? subgroupAdd(g_steps) : 0u);
  const uint aborted_sum = subgroupAdd(aborted);
  // No loop here: a limiter that fired during the last ray would cut a loop short and lose
  // counts of rays that did finish.
  if (subgroupElect()) {
    add_wide(HRPP_COUNTER_RAYS, sums[HRPP_COUNTER_RAYS]);
    add_wide(HRPP_COUNTER_INTERIOR, sums[HRPP_COUNTER_INTERIOR]);
    add_wide(HRPP_COUNTER_LEAVES, sums[HRPP_COUNTER_LEAVES]);
    add_wide(HRPP_COUNTER_TRIANGLES, sums[HRPP_COUNTER_TRIANGLES]);
    add_wide(HRPP_COUNTER_HITS, sums[HRPP_COUNTER_HITS]);
    add_wide(HRPP_COUNTER_STEPS, sums[HRPP_COUNTER_STEPS]);
    if (aborted_sum != 0u) atomicAdd(counters.aborted, aborted_sum);
  }
}

#endif  // HRPP_TRACE_KERNEL_GLSL
