// The HRPP stage's buffers besides the BVH and the class's rays (shaders/shared/hrpp_interface.h,
// HRPP_STAGE_BINDING_*): the class's hit array, the queue and its arrays (skip lists included),
// the table, and the prediction node of every triangle. Included by hrpp_predict(_any).comp and
// hrpp_resolve.comp, which enable 64-bit integers and atomics and declare `pc`
// (StagePushConstants).
#ifndef HRPP_STAGE_GLSL
#define HRPP_STAGE_GLSL

// Texel buffers are read without a sampler (texelFetch on utextureBuffer).
#extension GL_EXT_samplerless_texture_functions : require

#include "hrpp_interface.h"

// The arrays a ray is written to or read from as a whole are texel buffers (R32G32B32A32_UINT):
// on lavapipe one vec4 image store per lane costs what one 32-bit storage store does.
layout(set = 0, binding = HRPP_STAGE_BINDING_HITS, rgba32ui) uniform restrict uimageBuffer
    hit_texels;  // the class's hit array (Hit: 1 texel)
layout(std430, set = 0, binding = HRPP_STAGE_BINDING_QUEUE) restrict buffer QueueBuffer {
  PredictQueue queue;
};
layout(set = 0, binding = HRPP_STAGE_BINDING_QUEUE_RAYS, rgba32ui) uniform restrict writeonly
    uimageBuffer queue_ray_texels;  // Ray: 2 texels
layout(set = 0, binding = HRPP_STAGE_BINDING_QUEUE_ENTRIES, rgba32ui) uniform restrict
    uimageBuffer queue_entry_texels;  // QueueEntry: 1 texel
layout(set = 0, binding = HRPP_STAGE_BINDING_QUEUE_HITS) uniform utextureBuffer queue_hit_texels;

void store_hit(uint i, Hit h) {
  imageStore(hit_texels, int(i),
             uvec4(uint(h.prim), floatBitsToUint(h.t), floatBitsToUint(h.u), floatBitsToUint(h.v)));
}
Hit unpack_hit(uvec4 w) {
  return Hit(int(w.x), uintBitsToFloat(w.y), uintBitsToFloat(w.z), uintBitsToFloat(w.w));
}
Hit load_hit(uint i) { return unpack_hit(imageLoad(hit_texels, int(i))); }
Hit load_queue_hit(uint i) { return unpack_hit(texelFetch(queue_hit_texels, int(i))); }

void store_queue_ray(uint slot, Ray r) {
  imageStore(queue_ray_texels, int(2u * slot), uvec4(floatBitsToUint(r.origin), floatBitsToUint(r.tmin)));
  imageStore(queue_ray_texels, int(2u * slot + 1u), uvec4(floatBitsToUint(r.dir), floatBitsToUint(r.tmax)));
}
void store_queue_entry(uint slot, QueueEntry e) {
  imageStore(queue_entry_texels, int(slot), uvec4(e.ray, e.flags, e.key_lo, e.key_hi));
}
layout(set = 0, binding = HRPP_STAGE_BINDING_QUEUE_SKIPS, rgba32ui) uniform restrict writeonly
    uimageBuffer queue_skip_texels;  // HRPP_SKIP_NODES child references: 1 texel
void store_queue_skips(uint slot, ivec4 nodes) {
  imageStore(queue_skip_texels, int(slot), uvec4(nodes));
}
QueueEntry load_queue_entry(uint slot) {
  const uvec4 w = imageLoad(queue_entry_texels, int(slot));
  return QueueEntry(w.x, w.y, w.z, w.w);
}

// The prediction node (go-up level applied on the host: host/hrpp/prediction_node.h) of every
// triangle id, as a child reference; HRPP_EMPTY_NODE for ids in no leaf. Four ids a texel: a
// texel view reaches 2^29 ids where a storage buffer's range (128 MiB) would stop at 2^25.
layout(set = 0, binding = HRPP_STAGE_BINDING_NODE_OF_PRIM) uniform utextureBuffer
    hrpp_node_of_prim_texels;
int hrpp_node_of_prim(uint prim) {
  return int(texelFetch(hrpp_node_of_prim_texels, int(prim >> 2u))[prim & 3u]);
}

layout(set = 0, binding = HRPP_STAGE_BINDING_TAG_TEXELS) uniform utextureBuffer hrpp_tag_texels;
layout(set = 0, binding = HRPP_STAGE_BINDING_SLOT_TEXELS) uniform utextureBuffer hrpp_slot_texels;

// Tag i and node slot i through the texel views (4 words per texel).
uint64_t hrpp_fetch_tag(uint i) {
  const uvec4 t = texelFetch(hrpp_tag_texels, int(i >> 1u));
  const uvec2 w = (i & 1u) != 0u ? t.zw : t.xy;
  return uint64_t(w.x) | (uint64_t(w.y) << 32);
}
uint hrpp_fetch_slot(uint i) { return texelFetch(hrpp_slot_texels, int(i >> 2u))[i & 3u]; }

#define HRPP_TABLE_FETCH_TAG hrpp_fetch_tag
#define HRPP_TABLE_BASE HRPP_STAGE_BINDING_TABLE
#include "hrpp_table.glsl"

#endif  // HRPP_STAGE_GLSL
