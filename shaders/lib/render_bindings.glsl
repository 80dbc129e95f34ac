// Buffers, specialization constants and push constants of the render kernels
// (shaders/shared/render_interface.h), and the completion count every kernel reports.
#ifndef HRPP_RENDER_BINDINGS_GLSL
#define HRPP_RENDER_BINDINGS_GLSL

// Texel buffers are read without a sampler (texelFetch on utextureBuffer).
#extension GL_EXT_samplerless_texture_functions : require

#include "render_interface.h"
#include "surface_hit.h"

layout(local_size_x = HRPP_RENDER_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(constant_id = HRPP_FEATURE_TEXTURES) const bool kTextures = true;
layout(constant_id = HRPP_FEATURE_EMISSIVE_TRIANGLES) const bool kEmissiveTriangles = true;
layout(constant_id = HRPP_FEATURE_POINT_LIGHTS) const bool kPointLights = true;
layout(constant_id = HRPP_FEATURE_SPOT_LIGHTS) const bool kSpotLights = true;
layout(constant_id = HRPP_FEATURE_DIRECTIONAL_LIGHTS) const bool kDirectionalLights = true;
layout(constant_id = HRPP_FEATURE_ENVIRONMENT) const bool kEnvironment = true;
layout(constant_id = HRPP_FEATURE_METAL) const bool kMetal = true;
layout(constant_id = HRPP_FEATURE_GLASS) const bool kGlass = true;
layout(constant_id = HRPP_FEATURE_SPECULAR_LAYER) const bool kSpecularLayer = true;
layout(constant_id = HRPP_FEATURE_MATERIAL_TEXTURES) const bool kMaterialTextures = true;

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
layout(set = 0, binding = HRPP_RENDER_BINDING_HITS) uniform utextureBuffer hit_texels;
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
layout(set = 0, binding = HRPP_RENDER_BINDING_SHADE_TRIANGLES) uniform utextureBuffer shade_triangles;
layout(set = 0, binding = HRPP_RENDER_BINDING_SHADE_VERTICES) uniform utextureBuffer shade_vertices;
layout(set = 0, binding = HRPP_RENDER_BINDING_SHADE_ATTRIBUTES) uniform utextureBuffer shade_attributes;
layout(set = 0, binding = HRPP_RENDER_BINDING_MATERIALS) uniform utextureBuffer material_texels;
layout(set = 0, binding = HRPP_RENDER_BINDING_LIGHTS) uniform utextureBuffer light_texels;
layout(set = 0, binding = HRPP_RENDER_BINDING_RAY_TEXELS) uniform utextureBuffer ray_texels;
layout(set = 0, binding = HRPP_RENDER_BINDING_PATH_TEXELS) uniform utextureBuffer path_texels;
layout(set = 0, binding = HRPP_RENDER_BINDING_SHADOW_HITS) uniform utextureBuffer shadow_hit_texels;
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_TEXTURES) readonly restrict buffer TextureBuffer {
  GpuTexture textures[];
};
layout(std430, set = 0, binding = HRPP_RENDER_BINDING_TEXELS) readonly restrict buffer TexelBuffer {
  uint texels[];
};
layout(push_constant) uniform PushConstants { RenderPushConstants pc; };

// Records of the read-only arrays, one 16-byte texel per row of the struct.
uvec4 texel_at(utextureBuffer b, uint i) { return texelFetch(b, int(i)); }

Hit hit_of(uvec4 t) {
  return Hit(int(t.x), uintBitsToFloat(t.y), uintBitsToFloat(t.z), uintBitsToFloat(t.w));
}
Hit load_hit(uint i) { return hit_of(texel_at(hit_texels, i)); }
Hit load_shadow_hit(uint i) { return hit_of(texel_at(shadow_hit_texels, i)); }

Ray load_ray(uint i) {
  const vec4 a = uintBitsToFloat(texel_at(ray_texels, 2u * i));
  const vec4 b = uintBitsToFloat(texel_at(ray_texels, 2u * i + 1u));
  return Ray(a.xyz, a.w, b.xyz, b.w);
}

PathState load_path(uint i) {
  const uvec4 a = texel_at(path_texels, 2u * i);
  const uvec4 b = texel_at(path_texels, 2u * i + 1u);
  return PathState(uintBitsToFloat(a.xyz), a.w, b.x, b.y, b.z, uintBitsToFloat(b.w));
}

vec4 float_texel(utextureBuffer b, uint i) { return uintBitsToFloat(texel_at(b, i)); }

ShadeVertex load_shade_vertex(uint i) {
  const uvec4 a = texel_at(shade_vertices, i);
  return ShadeVertex(uintBitsToFloat(a.xyz), a.w);
}

ShadeAttributes load_shade_attributes(uint i, bool stored) {
  if (!stored) return default_shade_attributes();
  return ShadeAttributes(float_texel(shade_attributes, 2u * i),
                         float_texel(shade_attributes, 2u * i + 1u));
}

// Triangle i's shading data: its ShadeIndex and its corners' records.
ShadeTriangle load_shade_triangle(uint i) {
  const uvec4 c = texel_at(shade_triangles, i);
  const bool stored = (c.w & HRPP_SHADE_ATTRIBUTES) != 0u;
  return shade_triangle_of(ShadeIndex(c.x, c.y, c.z, c.w), load_shade_vertex(c.x),
                           load_shade_vertex(c.y), load_shade_vertex(c.z),
                           load_shade_attributes(c.x, stored), load_shade_attributes(c.y, stored),
                           load_shade_attributes(c.z, stored));
}

GpuMaterial load_material(uint i) {
  const uvec4 a = texel_at(material_texels, 5u * i);
  const uvec4 b = texel_at(material_texels, 5u * i + 1u);
  const uvec4 c = texel_at(material_texels, 5u * i + 2u);
  // The specular layer's texel only where a material has one (else f90 0: no layer), the
  // textures' only where one has metallic-roughness or emissive textures (else -1: none).
  const uvec4 d = kSpecularLayer ? texel_at(material_texels, 5u * i + 3u) : uvec4(0u);
  const ivec4 e = kMaterialTextures ? ivec4(texel_at(material_texels, 5u * i + 4u)) : ivec4(-1);
  return GpuMaterial(uintBitsToFloat(a.xyz), int(a.w), uintBitsToFloat(b.xyz),
                     uintBitsToFloat(b.w), uintBitsToFloat(c.x), uintBitsToFloat(c.y),
                     uintBitsToFloat(c.z), c.w, uintBitsToFloat(d.xyz), uintBitsToFloat(d.w),
                     e.x, e.y, e.z, e.w);
}

GpuLight load_light(uint i) {
  const uvec4 a = texel_at(light_texels, 4u * i);
  const uvec4 b = texel_at(light_texels, 4u * i + 1u);
  const uvec4 c = texel_at(light_texels, 4u * i + 2u);
  const uvec4 d = texel_at(light_texels, 4u * i + 3u);
  return GpuLight(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), uintBitsToFloat(b.w),
                  uintBitsToFloat(c.xyz), uintBitsToFloat(c.w), uintBitsToFloat(d.xyz),
                  uintBitsToFloat(d.w));
}

float light_cdf(uint i) { return uintBitsToFloat(texel_at(light_texels, 4u * i + 1u).w); }

// The probability that next-event estimation picks light i (its share of the cdf).
float light_pick_prob(uint i) { return light_cdf(i) - (i > 0u ? light_cdf(i - 1u) : 0.0); }

// One atomic per subgroup: the items this invocation finished (0 or 1) summed into
// queues.done[kernel] (HRPP_RENDER_DONE_*).
void report_done(uint kernel, uint finished) {
  const uint sum = subgroupAdd(finished);
  if (subgroupElect() && sum != 0u) atomicAdd(queues.done[kernel], sum);
}

#endif  // HRPP_RENDER_BINDINGS_GLSL
