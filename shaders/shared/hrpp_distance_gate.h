// The distance gate (gate G; hit-all rays, speculative mode). A speculative answer goes
// wrong when the ray has an occluder near its origin that its entry does not hold: rays that
// share a coarse key start up to a cell apart, and one of them meets a surface close by that
// the others pass (results/KEYS.md, "Bounce rays"). The gate accepts a true positive only when
// its t is at most G × the nearest hit that a traced ray of the same key found; a farther one
// bounds an exact trace instead (tmax = its t, as in exact mode), which answers it right.
// Every entry keeps that nearest hit as hrpp_nearest_word(t): 0 means none yet, and the nearest
// t has the largest word (non-negative floats order as their bits), so one atomicMax keeps it.
// One definition for the GPU table (shaders/lib/hrpp_table.glsl, hrpp_predict.glsl) and its CPU
// mirror (host/hrpp/reference_table.cpp, reference_predictor.cpp).
#ifndef HRPP_HRPP_DISTANCE_GATE_H
#define HRPP_HRPP_DISTANCE_GATE_H

#include "glsl_cpp.h"
#include "shared_fn.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

HRPP_INLINE uint hrpp_nearest_word(float t) { return ~floatBitsToUint(t > 0.0f ? t : 0.0f); }

// Whether the gate sends a true positive at t to an exact trace: its entry has seen a hit and t
// lies beyond gate × the nearest one (gate 0: the gate is off).
HRPP_INLINE bool hrpp_gated(float t, uint nearest_word, float gate) {
  return gate > 0.0f && nearest_word != 0u && t > gate * uintBitsToFloat(~nearest_word);
}

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_HRPP_DISTANCE_GATE_H
