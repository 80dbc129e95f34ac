// Interface of the HRPP kernels: binding slots, workgroup sizes and push constants of
// shaders/hrpp_*.comp. Included by the host (host/gpu/) and by GLSL; one definition.
#ifndef HRPP_HRPP_INTERFACE_H
#define HRPP_HRPP_INTERFACE_H

#include "hrpp_passes.h"
#include "hrpp_types.h"
#include "trace_interface.h"

// hrpp_hash_rays.comp: keys[i] = hash(rays[i]) under params.
#define HRPP_HASH_WORKGROUP_SIZE 64
#define HRPP_HASH_BINDING_RAYS 0
#define HRPP_HASH_BINDING_KEYS 1
#define HRPP_HASH_BINDING_PARAMS 2
#define HRPP_HASH_BINDING_COUNT 3

// The HRPP stage: hrpp_predict(_any).comp and hrpp_resolve.comp share one binding layout. The
// first six are the trace kernels' texel buffers (BVH arrays and the class's rays, the same
// slots as shaders/shared/trace_interface.h); then the class's hit array, the queue, the
// queued rays, their entries and the trace's hits of the queued rays.
#define HRPP_STAGE_BINDING_HITS 6
#define HRPP_STAGE_BINDING_QUEUE 7
#define HRPP_STAGE_BINDING_QUEUE_RAYS 8
#define HRPP_STAGE_BINDING_QUEUE_ENTRIES 9
#define HRPP_STAGE_BINDING_QUEUE_HITS 10
#define HRPP_STAGE_BINDING_TABLE 11  // the table's buffers: 11 + HRPP_TABLE_*
// The prediction node of every triangle id (a uniform texel buffer, 4 ids a texel).
#define HRPP_STAGE_BINDING_NODE_OF_PRIM 17
// The table's tags and node slots again, as uniform texel buffers (R32G32B32A32_UINT views): how
// hrpp_predict reads them (texel gathers; scattered storage loads are slow on lavapipe).
#define HRPP_STAGE_BINDING_TAG_TEXELS 18
#define HRPP_STAGE_BINDING_SLOT_TEXELS 19
// The queued rays' skip lists (fallback skip): per queued ray, the nodes its prediction
// tested without an answer (HRPP_TRACE_BINDING_SKIP_NODES of the skipping trace kernels).
#define HRPP_STAGE_BINDING_QUEUE_SKIPS 20
#define HRPP_STAGE_BINDING_COUNT 21
#define HRPP_RESOLVE_WORKGROUP_SIZE 64
// hrpp_predict's specialization constants: what a configuration does not use is compiled out
// (an inlined traversal costs even where no lane runs it, measured on lavapipe).
#define HRPP_SPEC_VERIFY_INTERIOR 0  // go-up > 0: predicted nodes may be interior nodes
#define HRPP_SPEC_COUNT_BASELINE 1   // count what a full traversal of each probed ray visits
// hrpp_predict's workgroup size (local_size_x_id): the device's subgroup size where it divides
// HRPP_TRACE_WORKGROUP_SIZE (gpu_predictor.cpp, predict_workgroup_size), so a workgroup is one
// subgroup (8 lanes on lavapipe, 32 on NVIDIA, 64 on many AMD parts). A workgroup still takes
// StagePushConstants::trace_group_rays rays, as one of the trace kernel's does: the dispatch
// sizes (the trace's own indirect arguments among them) stay those of the trace.
#define HRPP_SPEC_PREDICT_WORKGROUP 4
// 1: hrpp_predict writes each queued ray's skip list (fallback skip); 0 compiles it out.
#define HRPP_SPEC_SKIP_LIST 5

// The table's buffers at base + these offsets (the stage: base HRPP_STAGE_BINDING_TABLE;
// hrpp_insert: base 0): params, 64-bit tags, use stamps, node slots, requests, counters.
#define HRPP_TABLE_PARAMS 0
#define HRPP_TABLE_TAGS 1
#define HRPP_TABLE_STAMPS 2
#define HRPP_TABLE_SLOTS 3
#define HRPP_TABLE_REQUESTS 4
#define HRPP_TABLE_COUNTERS 5
#define HRPP_TABLE_BINDING_COUNT 6

#ifdef __cplusplus
namespace hrpp::gpu {
#endif
// hrpp_predict and hrpp_resolve.
struct StagePushConstants {
  uint rays_per_invocation;  // hrpp_predict: cap on the rays one invocation takes (loop limiter)
  uint canary_iterations;    // always 2 (shaders/lib/trace_kernel.glsl, loop_budget_left)
  uint trace_group_rays;     // rays per workgroup of the trace kernel over the queue
  uint pilot_stride;         // the pilot schedule's K, or the sample's stride
  uint pilot_pass;           // HRPP_PASS_* (shaders/shared/hrpp_passes.h)
  uint pad;
};

// hrpp_insert.comp: one invocation applies requests[first .. first + count) in index order (the
// deterministic batch order of host/hrpp/predictor_config.h).
struct InsertPushConstants {
  uint first;
  uint count;
  uint clock;  // use stamp of request `first`
  uint pad;
};
#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif
#define HRPP_INSERT_BATCH_MAX 256  // requests per dispatch: 256 × (64 + 64) loop steps < 65,535

#endif  // HRPP_HRPP_INTERFACE_H
