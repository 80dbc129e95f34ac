// Interface of the trace kernels (shaders/trace_closest.comp, shaders/trace_any.comp): binding
// slots, push constants, workgroup size and the counters block. Included by the host
// (host/gpu/gpu_tracer.cpp, which static_asserts the sizes) and by GLSL; one definition.
#ifndef HRPP_TRACE_INTERFACE_H
#define HRPP_TRACE_INTERFACE_H

#include "gpu_types.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

// Deepest traversal stack (one entry per tree level). The same value as host/bvh/gpu_layout.h,
// which refuses deeper trees; the #ifndef keeps the two definitions one token sequence.
#ifndef HRPP_STACK_SIZE
#define HRPP_STACK_SIZE 64
#endif

#define HRPP_TRACE_WORKGROUP_SIZE 64

// NODES, LEAVES, the three TRIANGLES planes and RAYS are uniform texel buffers
// (R32G32B32A32_UINT views of the BvhNode, BvhLeaf, TriangleRecord and Ray arrays:
// shaders/lib/texel_fetch.glsl); HITS and COUNTERS are storage buffers. The triangle records are
// stored as three planes, texel k of record i at index i of plane k (TRIANGLES + k), so each
// plane has one texel a triangle and a scene may have 2^27 triangles (maxTexelBufferElements)
// where one array of 3-texel records would stop at 2^27 / 3.
#define HRPP_TRACE_BINDING_NODES 0
#define HRPP_TRACE_BINDING_LEAVES 1
#define HRPP_TRACE_BINDING_TRIANGLES 2  // planes 2, 3, 4
#define HRPP_TRACE_TRIANGLE_PLANES 3
#define HRPP_TRACE_BINDING_RAYS 5
#define HRPP_TRACE_BINDING_HITS 6
#define HRPP_TRACE_BINDING_COUNTERS 7
#define HRPP_TRACE_BINDING_COUNT 8
// The indexed kernels (trace_closest_indexed, trace_any_indexed: HRPP_TRACE_INDEXED 1) also read
// a ray index list: position j of the dispatch traces ray list[j] and writes its hit at that
// ray's index, so the rays are traced in the list's order while rays and hits stay where they
// are. The list is a uniform texel buffer of uint, 4 per texel (R32G32B32A32_UINT); the plain
// kernels have no such binding.
#define HRPP_TRACE_BINDING_RAY_INDICES 8
#define HRPP_TRACE_INDEXED_BINDING_COUNT 9
// The skipping kernels (trace_closest_skipping, trace_any_skipping: HRPP_TRACE_SKIPPING 1) trace
// HRPP's queue with fallback skip: position j also reads entry j of a skip list, the
// nodes (child references, HRPP_EMPTY_NODE for none) that ray's prediction already tested
// without finding a hit before its tmax, and the traversal does not enter them: what they hold is
// known not to be the answer. A uniform texel buffer of HRPP_SKIP_NODES ints per entry (one
// R32G32B32A32_UINT texel); the other kernels have no such binding.
#define HRPP_TRACE_BINDING_SKIP_NODES 8
#define HRPP_TRACE_SKIPPING_BINDING_COUNT 9
#define HRPP_SKIP_NODES 4

// The ray-query kernels (trace_rayquery_closest, trace_rayquery_any: the driver's traversal,
// host/gpu/ray_query_tracer.h) bind the top-level acceleration structure, the rays (a uniform
// texel buffer, as above), the hits (a storage texel buffer) and the TraceCounters, and take
// TracePushConstants (rays_per_invocation and canary_iterations), persistent invocations as the
// trace kernels'.
#define HRPP_RAY_QUERY_BINDING_SCENE 0
#define HRPP_RAY_QUERY_BINDING_RAYS 1
#define HRPP_RAY_QUERY_BINDING_HITS 2
#define HRPP_RAY_QUERY_BINDING_COUNTERS 3
#define HRPP_RAY_QUERY_BINDING_COUNT 4

// Float bits of the slab test's far-distance scale 1 + 2γ(3) (host/trace/slab_test.h); GLSL has
// no hex floats, the host static_asserts that the bits match kSlabFarScale.
#define HRPP_SLAB_FAR_SCALE_BITS 0x3F800003u
// Safe reciprocal (host/trace/ray_setup.h): |d| < 2^-80 becomes ±2^80; the slab test takes a
// reciprocal of magnitude 2^80 or more as "parallel to that axis".
#define HRPP_TWO_POW_M80_BITS 0x17800000u
#define HRPP_TWO_POW_80_BITS 0x67800000u

// 64-bit counters kept as (lo, hi) pairs of 32-bit words so the kernels need 32-bit atomics only
// (a carry out of lo adds 1 to hi). Index = 2 × HRPP_COUNTER_*.
#define HRPP_COUNTER_RAYS 0              // rays traced to completion (result written)
#define HRPP_COUNTER_INTERIOR 1          // interior nodes whose two child boxes were tested
#define HRPP_COUNTER_LEAVES 2            // leaves whose triangles were tested
#define HRPP_COUNTER_TRIANGLES 3         // triangles tested
#define HRPP_COUNTER_HITS 4              // rays that hit (any-hit: occluded)
#define HRPP_COUNTER_STEPS 5             // subgroup iterations of the interior-node loop
                                         // (HRPP_SPEC_COUNT_STEPS; else 0)
#define HRPP_COUNTER_COUNT 6

// Specialisation constant of the trace kernels (shaders/lib/traversal.glsl): 1 counts
// HRPP_COUNTER_STEPS, from which the lanes' use of the interior loop follows (interior nodes /
// (steps × subgroup size)); 0 (the default) compiles the count out. Its id is not one of
// hrpp_predict's (HRPP_SPEC_* in hrpp_interface.h), which includes the same traversal.
#define HRPP_SPEC_COUNT_STEPS 2
// Which nodes the node array holds (--bvh-nodes; host/bvh/wide_nodes.h), and so which traversal
// the trace kernels run: HRPP_NODES_BINARY (BvhNodes: the default, and hrpp_predict's),
// HRPP_NODES_WIDE (WideNodes) or HRPP_NODES_WIDE_FLOAT (WideFloatNodes).
#define HRPP_SPEC_NODE_FORMAT 3
#define HRPP_NODES_BINARY 0u
#define HRPP_NODES_WIDE 1u
#define HRPP_NODES_WIDE_FLOAT 2u

struct TraceCounters {
  uint next_ray;   // persistent fetch cursor (atomicAdd by one lane per subgroup)
  uint aborted;    // rays whose traversal was cut short by a loop limiter (lavapipe): never valid
  uint ray_count;  // rays in this dispatch: written by the host, or copied on the device from a
                   // queue counter for an indirect dispatch (GpuTracer::record_indirect)
  uint pad1;
  uint wide[2 * HRPP_COUNTER_COUNT];  // (lo, hi) pairs, see HRPP_COUNTER_*
};

// The limiter probe's loop count, set by the host as a push constant (never a literal in GLSL).
#define HRPP_CANARY_ITERATIONS 2u

struct TracePushConstants {
  uint rays_per_invocation;  // cap on the rays one invocation traces (loop limiter)
  uint canary_iterations;    // HRPP_CANARY_ITERATIONS: a loop bound the compiler cannot know
                             // (the limiter probe, shaders/lib/loop_limiter.glsl)
  uint serial;  // 1: one ray per subgroup (the CPU reference's node visiting order)
  uint pad1;
};

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_TRACE_INTERFACE_H
