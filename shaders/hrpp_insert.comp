// hrpp_insert: applies the deferred insert requests of one batch (shaders/lib/hrpp_table.glsl)
// in request order, in a single invocation: the deterministic order that the CPU reference
// predictor (host/hrpp/reference_predictor.h) reproduces. At most HRPP_INSERT_BATCH_MAX requests
// per dispatch, far below lavapipe's loop limit (docs/DEVICES.md, "Lavapipe").
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require

#define HRPP_TABLE_BASE 0
#include "lib/hrpp_table.glsl"

layout(local_size_x = 1, local_size_y = 1, local_size_z = 1) in;

layout(push_constant) uniform PushConstants { InsertPushConstants pc; };

void main() {
  HRPP_INSERT_OUTCOME_COUNTERS(HRPP_DECLARE_COUNT)
  for (uint i = 0u; i < pc.count; ++i) {
    const InsertRequest r = hrpp_requests[pc.first + i];
    if (r.node == HRPP_EMPTY_NODE) continue;
    const uint64_t key = uint64_t(r.key_lo) | (uint64_t(r.key_hi) << 32);
    const uint outcome = hrpp_table_insert(key, r.node, r.t, pc.clock + i, count_evictions);
    if (outcome == kHrppInserted) ++count_inserts;
    else if (outcome == kHrppPresent) ++count_insert_present;
    else ++count_insert_drops;
  }
  HRPP_INSERT_OUTCOME_COUNTERS(HRPP_ADD_COUNT)
}
