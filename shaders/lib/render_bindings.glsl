// Buffers, specialization constants and push constants of the render kernels
// (shaders/shared/render_interface.h), and the completion count every kernel reports.
#ifndef HRPP_RENDER_BINDINGS_GLSL
#define HRPP_RENDER_BINDINGS_GLSL

#include "render_interface.h"

layout(local_size_x = HRPP_RENDER_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(constant_id = HRPP_FEATURE_TEXTURES) const bool kTextures = true;
layout(constant_id = HRPP_FEATURE_EMISSIVE_TRIANGLES) const bool kEmissiveTriangles = true;
layout(constant_id = HRPP_FEATURE_POINT_LIGHTS) const bool kPointLights = true;
layout(constant_id = HRPP_FEATURE_SPOT_LIGHTS) const bool kSpotLights = true;
layout(constant_id = HRPP_FEATURE_DIRECTIONAL_LIGHTS) const bool kDirectionalLights = true;
layout(constant_id = HRPP_FEATURE_ENVIRONMENT) const bool kEnvironment = true;
layout(constant_id = HRPP_FEATURE_METAL) const bool kMetal = true;
layout(constant_id = HRPP_FEATURE_GLASS) const bool kGlass = true;

layout(std430, set = 0, binding = HRPP_RENDER_BINDING_PARAMS) readonly restrict buffer ParamBuffer {
  RenderParams params;
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_PATHS) restrict buffer PathBuffer {
  PathState paths[];
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_NEXT_PATHS) restrict buffer NextPathBuffer {
  PathState next_paths[];
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_RAYS) restrict buffer RayBuffer {
  Ray rays[];
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_HITS) readonly restrict buffer HitBuffer {
  Hit hits[];
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_NEXT_RAYS) restrict buffer NextRayBuffer {
  Ray next_rays[];
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_SHADOW_RAYS) restrict buffer ShadowRayBuffer {
  Ray shadow_rays[];
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_SHADOWS) restrict buffer ShadowBuffer {
  ShadowRecord shadows[];
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_IMAGE) restrict buffer ImageBuffer {
  vec4 image[];
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_QUEUES) restrict buffer QueueBuffer {
  RenderQueues queues;
};
layout(set = 0, binding = HRPP_RENDER_BINDING_SHADE_TRIANGLES) uniform usamplerBuffer shade_triangles;
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_MATERIALS) readonly restrict buffer MaterialBuffer {
  GpuMaterial materials[];
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_LIGHTS) readonly restrict buffer LightBuffer {
  GpuLight lights[];
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_TEXTURES) readonly restrict buffer TextureBuffer {
  GpuTexture textures[];
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_TEXELS) readonly restrict buffer TexelBuffer {
  uint texels[];
};
layout(push_constant) uniform PushConstants { RenderPushConstants pc; };

// One atomic per subgroup: the items this invocation finished (0 or 1) summed.
void report_done(uint finished) {
  const uint sum = subgroupAdd(finished);
  if (subgroupElect() && sum != 0u) atomicAdd(queues.done, sum);
}

#endif  // HRPP_RENDER_BINDINGS_GLSL
