// HRPP (hash-based ray path prediction): the constants and structs that the C++ side
// (host/hrpp/, host/front/gpu_predictor.cpp) and the GLSL side (shaders/lib/hrpp_*.glsl,
// shaders/hrpp_*.comp) share. One definition each; the host static_asserts sizes
// (host/hrpp/ray_hash.h, host/hrpp/predictor_config.h, host/front/gpu_predictor.cpp).
#ifndef HRPP_HRPP_TYPES_H
#define HRPP_HRPP_TYPES_H

#include "gpu_types.h"

#ifdef __cplusplus
namespace hrpp::gpu {
using uint64_t = std::uint64_t;
#endif

// Hash kinds (hash). Every kind takes a precision N = 1..8 (hash_bits) and gives a key of at
// most 48 bits; the exact definitions are in shaders/lib/hrpp_hash.glsl (the C++ mirror,
// host/hrpp/ray_hash.cpp, repeats them operation for operation).
#define HRPP_HASH_IEEE 0            // the paper's IEEE-754 bit hash with the xor swizzle
#define HRPP_HASH_GRID_SPHERICAL 1  // after MICRO'21: origin on a 2^N grid, direction as θ/φ
                                    // bins (2^D each; D = N unless hash_dir_bits says)
#define HRPP_HASH_TWO_POINT 2       // origin and a point further along the ray, both on grids
#define HRPP_HASH_LIGHT 3           // light space: the ray's end (the light) on a grid and the
                                    // direction from it to the origin in octahedral cells
#define HRPP_HASH_LIGHT_DEPTH 4     // HRPP_HASH_LIGHT plus the receiver's distance from the light
#define HRPP_HASH_MICRO21 5         // MICRO'21's own grid-spherical hash as its simulator has it:
                                    // origin cell xor 32° direction bins (micro21_bins.h)
#define HRPP_HASH_KIND_COUNT 6
#define HRPP_HASH_BITS_MAX 8

// Keys are < 2^48, so a tag of all ones never equals a key: it marks an empty table entry.
#define HRPP_KEY_BITS 48

// Parameters of one hash: what the kernels need besides the ray. The grid values are computed
// once on the host (host/hrpp/ray_hash.cpp, make_hash_params) and used as floats by both sides,
// so neither side divides by the scene extent itself.
//   grid_lo, grid_scale: origin cell along axis a = (o[a] - grid_lo[a]) * grid_scale[a], where
//     grid_scale[a] = 2^N / extent[a] of the scene box (0 for a flat axis: one cell);
//   far_lo, far_scale: the same for the two-point hash's second point, on the scene box grown by
//     `reach` on every side; for the light-space keys, the light end's grid (second_bits per
//     axis) over the scene box itself;
//   reach: the scene box's largest extent, the max-norm distance of the second point;
//   second_bits: the light-space keys' light-end grid precision, min(N + 1, 8); grid-spherical:
//     the direction bins' precision (hash_dir_bits, default N); micro21: its sphere bits, 3;
//     0 for the others.
struct HashParams {
  vec3 grid_lo;
  uint kind;  // HRPP_HASH_*
  vec3 grid_scale;
  uint bits;  // precision N, 1..HRPP_HASH_BITS_MAX
  vec3 far_lo;
  float reach;
  vec3 far_scale;
  uint second_bits;
};


// Hit-all modes (--hrpp-mode). Hit-any rays are always exact: any hit answers them.
#define HRPP_MODE_SPECULATIVE 0  // the paper: accept the closest hit among the predicted nodes
#define HRPP_MODE_EXACT 1        // use that hit's t as tmax of a full traversal: = HRPP off

// Replacement when an insert finds no room (table_policy).
#define HRPP_POLICY_NONE 0  // the paper: drop the insert
#define HRPP_POLICY_LRU 1   // evict the set's least recently used way (node list full: see
                            // shaders/lib/hrpp_table.glsl)
#define HRPP_POLICY_FIFO 2  // evict the way whose key came in first (a probe hit writes nothing)
#define HRPP_POLICY_MICRO21 3  // MICRO'21's table: a key's set is its bits xor-folded to the set
                               // count's width (ray-predictor.cc, compute_index), then as lru
#define HRPP_POLICY_COUNT \
  4  // a new policy: its branches in shaders/lib/hrpp_table.glsl and
     // host/hrpp/reference_table.cpp, its name in predictor_config.h

// Ray classes: each has its own table, switch, counters and
// kernel times (host/trace/ray_class.h names them). Camera and bounce rays are hit-all (closest
// hit), shadow rays hit-any.
#define HRPP_RAY_CLASS_CAMERA 0
#define HRPP_RAY_CLASS_BOUNCE 1
#define HRPP_RAY_CLASS_SHADOW 2
#define HRPP_RAY_CLASS_COUNT 3

// An empty node slot; node slots hold BVH child references (>= 0 interior node, < 0 leaf
// ~index), as BvhNode::link does.
#define HRPP_EMPTY_NODE 0x7FFFFFFF

// One predictor (a table and how it is used); one per ray class, each in buffers of its own.
// Table: sets (a power of two) × ways entries, each a 64-bit tag (the full key; all ones =
// empty), a use stamp and `nodes` node slots; with the distance gate also the nearest hit its
// key's traced rays found. Bytes: sets × ways × (8 + 4 + 4 × nodes), + 4 with the gate; times
// sm_tables.
struct PredictorParams {
  HashParams hash;
  uint sets;
  uint ways;
  uint nodes;   // node slots per entry
  uint policy;  // HRPP_POLICY_*
  uint go_up;   // go-up level L: the ancestor L levels above the leaf that held the hit
  uint mode;    // HRPP_MODE_* (hit-all)
  uint insert_deferred;  // 0: hrpp_resolve inserts; 1: it writes insert requests (batches)
  uint count_baseline;   // 1: also time-free count what a full traversal of each probed ray
                         //    visits (savings) and, speculative, whether the answer was wrong
  uint clock;  // use stamp of the dispatch's first ray (LRU); ray i of the dispatch: clock + i
  uint serial;  // 1: one ray per subgroup (the CPU reference's node order; deterministic runs)
  float go_up_size;  // then further up while the node's box is smaller than this fraction of
                     // the scene box (host/hrpp/prediction_node.h; 0: levels only)
  float gate;  // the distance gate G (shaders/shared/hrpp_distance_gate.h; 0: off)
  uint sm_tables;  // K independent tables of sets × ways entries, one per SM of a hardware
                   // predictor (shaders/shared/hrpp_table_set.h, hrpp_sm_key); 0 or 1: one
  uint pad0, pad1, pad2;
};

// The HRPP stage's queue of one trace (shaders/hrpp_predict.comp → the trace kernel →
// shaders/hrpp_resolve.comp): rays the prediction did not answer, compacted. `trace_groups` and
// `resolve_groups` are VkDispatchIndirectCommands that hrpp_predict raises as it appends;
// `predict_groups` is hrpp_predict's own over a pass of a fraction of the rays
// (shaders/hrpp_pass_args.comp).
struct PredictQueue {
  uint next_ray;   // hrpp_predict's fetch cursor
  uint ray_count;  // rays to predict: written by the host or copied from a queue on the device
  uint queued;     // rays appended to the queue (the trace's ray count)
  uint resolved;   // rays answered by their prediction alone (never queued)
  uint aborted;    // rays whose prediction a loop limiter cut short
  uint resolve_done;  // queue entries hrpp_resolve answered
  uint queue_hits;    // of those, answers that are hits
  uint pad;
  uint trace_groups[4];    // x, y, z (+ pad): workgroups of the trace kernel over the queue
  uint resolve_groups[4];  // x, y, z (+ pad): workgroups of hrpp_resolve
  uint predict_groups[4];  // x, y, z (+ pad): workgroups of hrpp_predict over a pilot or sample pass
};

// A queued ray's origin: its index in the class's ray array, its key and how it was probed.
#define HRPP_QUEUE_PROBED 1u   // the ray probed the table (valid): a hit is inserted
#define HRPP_QUEUE_BOUNDED 2u  // a true positive of exact mode or of the distance gate: tmax =
                               // the predicted t, and the predicted hit waits in the hit array
struct QueueEntry {
  uint ray;
  uint flags;  // HRPP_QUEUE_*
  uint key_lo;
  uint key_hi;
};

// An insert request (deferred inserts): the node a ray's full traversal found, under its key.
struct InsertRequest {
  uint key_lo;
  uint key_hi;
  int node;  // HRPP_EMPTY_NODE: nothing to insert
  float t;   // the hit's t (the distance gate's nearest hit)
};

// Predictor counters of one ray class, summed over a dispatch (64-bit atomics). One list,
// expanded by both sides: X(NAME, key, index) gives the index constant HRPP_PC_NAME, the JSON key
// `key` (host) and the kernels' count variables (count_<key>, HRPP_DECLARE_COUNT).
//   probes = predictor_hits + negatives; predictor_hits = true_positives + false_positives;
//   insert_requests = inserts + insert_present + insert_drops.
// Interior nodes / leaves / triangles visited are TraceCounters' (they include verification).
// Counted by hrpp_predict:
//   verify_*: nodes visited testing predicted nodes;
//   baseline_interior, baseline_leaves, baseline_triangles: count_baseline, what a full
//     traversal visits;
//   wrong_closest: count_baseline, speculative: accepted hit != closest hit;
//   gated: true positives of hit-all rays that the distance gate sent to an exact trace.
#define HRPP_PREDICT_COUNTERS(X)                   \
  X(PROBES, probes, 0u)                            \
  X(PREDICTOR_HITS, predictor_hits, 1u)            \
  X(TRUE_POSITIVES, true_positives, 2u)            \
  X(FALSE_POSITIVES, false_positives, 3u)          \
  X(NEGATIVES, negatives, 4u)                      \
  X(VERIFY_INTERIOR, verify_interior, 5u)          \
  X(VERIFY_LEAVES, verify_leaves, 6u)              \
  X(VERIFY_TRIANGLES, verify_triangles, 7u)        \
  X(BASELINE_INTERIOR, baseline_interior, 8u)      \
  X(WRONG_CLOSEST, wrong_closest, 9u)              \
  X(GATED, gated, 10u)                             \
  X(BASELINE_LEAVES, baseline_leaves, 11u)         \
  X(BASELINE_TRIANGLES, baseline_triangles, 12u)
// The outcomes of table inserts (hrpp_resolve, hrpp_insert): node stored, node already in the
// entry, no room (policy none, or a lost replacement race), entries or nodes replaced (lru).
#define HRPP_INSERT_OUTCOME_COUNTERS(X)            \
  X(INSERTS, inserts, 14u)                         \
  X(INSERT_PRESENT, insert_present, 15u)           \
  X(INSERT_DROPS, insert_drops, 16u)               \
  X(EVICTIONS, evictions, 17u)
#define HRPP_INSERT_COUNTERS(X)                    \
  X(INSERT_REQUESTS, insert_requests, 13u)         \
  HRPP_INSERT_OUTCOME_COUNTERS(X)
#define HRPP_PREDICTOR_COUNTERS(X) HRPP_PREDICT_COUNTERS(X) HRPP_INSERT_COUNTERS(X)

#ifdef __cplusplus
}  // namespace hrpp::gpu
#define HRPP_PC_CONSTANT(NAME, key, index) inline constexpr std::uint32_t HRPP_PC_##NAME = index;
#else
#define HRPP_PC_CONSTANT(NAME, key, index) const uint HRPP_PC_##NAME = index;
#endif
HRPP_PREDICTOR_COUNTERS(HRPP_PC_CONSTANT)
#undef HRPP_PC_CONSTANT
#ifdef __cplusplus
namespace hrpp::gpu {
#endif
#define HRPP_PC_COUNT 18

struct PredictorCounters {
  uint64_t c[HRPP_PC_COUNT];
#ifdef __cplusplus
  PredictorCounters& operator+=(const PredictorCounters& o) {
    for (int i = 0; i < HRPP_PC_COUNT; ++i) c[i] += o.c[i];
    return *this;
  }
#endif
};

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_HRPP_TYPES_H
