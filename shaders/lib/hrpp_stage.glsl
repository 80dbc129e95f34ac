// The HRPP stage's buffers besides the BVH and the class's rays (shaders/shared/hrpp_interface.h,
// HRPP_STAGE_BINDING_*): the class's hit array, the queue and its arrays, the table, and the
// prediction node of every triangle. Included by hrpp_predict(_any).comp and hrpp_resolve.comp,
// which enable 64-bit integers and atomics and declare `pc` (StagePushConstants).
#ifndef HRPP_STAGE_GLSL
#define HRPP_STAGE_GLSL

#include "hrpp_interface.h"

layout(std430, set = 0, binding = HRPP_STAGE_BINDING_HITS) restrict buffer HitBuffer {
  Hit hits[];
};
layout(std430, set = 0, binding = HRPP_STAGE_BINDING_QUEUE) restrict buffer QueueBuffer {
  PredictQueue queue;
};
layout(std430, set = 0, binding = HRPP_STAGE_BINDING_QUEUE_RAYS) restrict buffer QueueRayBuffer {
  Ray queue_rays[];
};
layout(std430, set = 0, binding = HRPP_STAGE_BINDING_QUEUE_ENTRIES) restrict buffer
    QueueEntryBuffer {
  QueueEntry queue_entries[];
};
layout(std430, set = 0, binding = HRPP_STAGE_BINDING_QUEUE_HITS) readonly restrict buffer
    QueueHitBuffer {
  Hit queue_hits[];
};
// The prediction node (go-up level applied on the host: host/hrpp/prediction_node.h) of every
// triangle id, as a child reference; HRPP_EMPTY_NODE for ids in no leaf.
layout(std430, set = 0, binding = HRPP_STAGE_BINDING_NODE_OF_PRIM) readonly restrict buffer
    HrppNodeOfPrimBuffer {
  int hrpp_node_of_prim[];
};

#define HRPP_TABLE_BASE HRPP_STAGE_BINDING_TABLE
#include "hrpp_table.glsl"

#endif  // HRPP_STAGE_GLSL
