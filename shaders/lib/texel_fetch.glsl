// The trace kernels' inputs (the BVH arrays and the rays of shaders/shared/gpu_types.h) read
// through uniform texel buffers (R32G32B32A32_UINT views, host/vk/texel_view.h): a BvhNode is 4
// texels (a WideNode too; a WideFloatNode 7), a BvhLeaf 1, a TriangleRecord 3 (one in each of the
// three triangle planes), a Ray 2; bits are reinterpreted, never converted, so values are exactly
// the host's.
// Why not storage buffers: on lavapipe a per-lane storage-buffer load walks the lanes one 32-bit
// word at a time, a texel fetch gathers all lanes' 16-byte texels at once (DECISIONS.md).
#ifndef HRPP_TEXEL_FETCH_GLSL
#define HRPP_TEXEL_FETCH_GLSL

// Texel buffers are read without a sampler (texelFetch on utextureBuffer).
#extension GL_EXT_samplerless_texture_functions : require

layout(set = 0, binding = HRPP_TRACE_BINDING_NODES) uniform utextureBuffer node_texels;
layout(set = 0, binding = HRPP_TRACE_BINDING_LEAVES) uniform utextureBuffer leaf_texels;
layout(set = 0, binding = HRPP_TRACE_BINDING_TRIANGLES) uniform utextureBuffer triangle_plane0;
layout(set = 0, binding = HRPP_TRACE_BINDING_TRIANGLES + 1) uniform utextureBuffer triangle_plane1;
layout(set = 0, binding = HRPP_TRACE_BINDING_TRIANGLES + 2) uniform utextureBuffer triangle_plane2;

BvhNode load_node(int index) {
  const int t = 4 * index;
  BvhNode n;
  n.left_xy = uintBitsToFloat(texelFetch(node_texels, t));
  n.right_xy = uintBitsToFloat(texelFetch(node_texels, t + 1));
  n.lr_z = uintBitsToFloat(texelFetch(node_texels, t + 2));
  n.link = ivec4(texelFetch(node_texels, t + 3));
  return n;
}

// A WideNode (--bvh-nodes wide4) in place of BvhNodes: the same 4 texels per node.
WideNode load_wide_node(int index) {
  const int t = 4 * index;
  const uvec4 a = texelFetch(node_texels, t);
  WideNode n;
  n.origin = uintBitsToFloat(a.xyz);
  n.exponents = a.w;
  n.child = ivec4(texelFetch(node_texels, t + 1));
  n.lo = texelFetch(node_texels, t + 2);
  n.hi = texelFetch(node_texels, t + 3);
  return n;
}

// A WideFloatNode (--bvh-nodes wide4-float): 7 texels per node.
WideFloatNode load_wide_float_node(int index) {
  const int t = 7 * index;
  WideFloatNode n;
  n.lo_x = uintBitsToFloat(texelFetch(node_texels, t));
  n.hi_x = uintBitsToFloat(texelFetch(node_texels, t + 1));
  n.lo_y = uintBitsToFloat(texelFetch(node_texels, t + 2));
  n.hi_y = uintBitsToFloat(texelFetch(node_texels, t + 3));
  n.lo_z = uintBitsToFloat(texelFetch(node_texels, t + 4));
  n.hi_z = uintBitsToFloat(texelFetch(node_texels, t + 5));
  n.child = ivec4(texelFetch(node_texels, t + 6));
  return n;
}

BvhLeaf load_leaf(int index) {
  const uvec4 w = texelFetch(leaf_texels, index);
  return BvhLeaf(w.x, w.y, int(w.z), w.w);
}

TriangleRecord load_triangle(uint index) {
  const int t = int(index);
  const uvec4 a = texelFetch(triangle_plane0, t);
  const uvec4 b = texelFetch(triangle_plane1, t);
  const uvec4 c = texelFetch(triangle_plane2, t);
  return TriangleRecord(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w,
                        uintBitsToFloat(c.xyz), c.w);
}

#define HRPP_RAYS_BINDING HRPP_TRACE_BINDING_RAYS
#include "ray_fetch.glsl"

#endif  // HRPP_TEXEL_FETCH_GLSL
