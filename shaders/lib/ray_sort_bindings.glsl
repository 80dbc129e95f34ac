// Buffers and push constants of the ray reordering kernels (shaders/shared/ray_sort_interface.h),
// and the completion count each scatter and the gather report. Rays are read as 16-byte texels
// and the gather writes them with imageStore (docs/DEVICES.md, "Texel buffers").
#ifndef HRPP_RAY_SORT_BINDINGS_GLSL
#define HRPP_RAY_SORT_BINDINGS_GLSL

// Texel buffers are read without a sampler (texelFetch on utextureBuffer).
#extension GL_EXT_samplerless_texture_functions : require

#include "ray_sort_interface.h"

layout(set = 0, binding = HRPP_SORT_BINDING_RAYS) uniform utextureBuffer ray_texels;
layout(std430, set = 0, binding = HRPP_SORT_BINDING_ITEMS) restrict buffer ItemBuffer {
  uvec2 items[];  // (key, index of the ray in queue order)
};
layout(std430, set = 0, binding = HRPP_SORT_BINDING_COUNTS) restrict buffer CountBuffer {
  uint done[HRPP_SORT_PASSES + 1];  // items placed by each scatter pass and by the gather
  uint counts[];                    // [digit * blocks + block]
};
layout(std430, set = 0, binding = HRPP_SORT_BINDING_ORDER) restrict buffer OrderBuffer {
  uint order[];  // order[j]: the queue index of the ray at sorted position j
};
layout(set = 0, binding = HRPP_SORT_BINDING_SORTED_RAYS, rgba32ui) uniform writeonly restrict
    uimageBuffer sorted_rays;
layout(push_constant) uniform PushConstants { RaySortPushConstants pc; };

uint sort_digit(uint key) { return (key >> pc.shift) & uint(HRPP_SORT_BINS - 1); }

// The last radix pass (the most significant digit) writes the order instead of items.
bool last_pass() { return pc.shift == uint((HRPP_SORT_PASSES - 1) * HRPP_SORT_DIGIT_BITS); }

// Adds this subgroup's placed items to done[slot], one atomicAdd per subgroup (straight-line
// code: nothing the loop limiter could cut short).
void report_placed(uint slot, uint placed) {
  const uint sum = subgroupAdd(placed);
  if (subgroupElect() && sum != 0u) atomicAdd(done[slot], sum);
}

#endif  // HRPP_RAY_SORT_BINDINGS_GLSL
