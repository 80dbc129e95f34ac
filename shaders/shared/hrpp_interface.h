// Interface of the HRPP kernels: binding slots, workgroup sizes and push constants of
// shaders/hrpp_*.comp. Included by the host (host/gpu/) and by GLSL; one definition.
#ifndef HRPP_HRPP_INTERFACE_H
#define HRPP_HRPP_INTERFACE_H

#include "hrpp_types.h"

// hrpp_hash_rays.comp: keys[i] = hash(rays[i]) under params.
#define HRPP_HASH_WORKGROUP_SIZE 64
#define HRPP_HASH_BINDING_RAYS 0
#define HRPP_HASH_BINDING_KEYS 1
#define HRPP_HASH_BINDING_PARAMS 2
#define HRPP_HASH_BINDING_COUNT 3

// The predictor's buffers in the trace kernels with HRPP (trace_closest_hrpp, trace_any_hrpp):
// after the trace kernels' own bindings (shaders/shared/trace_interface.h).
#define HRPP_PREDICT_BINDING_FIRST 6
#define HRPP_PREDICT_BINDING_COUNT 13  // bindings 0..12 in all

// The table's buffers at base + these offsets (trace kernels: base HRPP_PREDICT_BINDING_FIRST;
// hrpp_insert: base 0): params, 64-bit tags, use stamps, node slots, requests, counters.
#define HRPP_TABLE_PARAMS 0
#define HRPP_TABLE_TAGS 1
#define HRPP_TABLE_STAMPS 2
#define HRPP_TABLE_SLOTS 3
#define HRPP_TABLE_REQUESTS 4
#define HRPP_TABLE_COUNTERS 5
#define HRPP_TABLE_BINDING_COUNT 6
// Trace kernels only: the prediction node (go-up level applied) of every triangle id, as a child
// reference (host/hrpp/prediction_node.h); HRPP_EMPTY_NODE for ids in no leaf.
#define HRPP_PREDICT_NODE_OF_PRIM 6

// hrpp_insert.comp: one invocation applies requests[first .. first + count) in index order (the
// deterministic batch order of host/hrpp/predictor_config.h).
#ifdef __cplusplus
namespace hrpp::gpu {
#endif
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
