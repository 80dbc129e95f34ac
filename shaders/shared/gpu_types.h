// The one definition of every struct that C++ and GLSL share.
//
// Included by the host (C++20, glm) and by the compute shaders (GLSL 4.60, std430). Every struct
// is built from 16-byte rows so std430 and C++ agree without padding rules; the C++ side
// static_asserts every size and offset (host/bvh/gpu_layout.h).
#ifndef HRPP_GPU_TYPES_H
#define HRPP_GPU_TYPES_H

// The tmax of a ray without an end (camera, continuation and directional-light shadow rays):
// finite, so tmax arithmetic never meets infinity.
#define HRPP_RAY_TMAX_FAR 3.0e38

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace hrpp::gpu {
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using uvec4 = glm::uvec4;
using uint = std::uint32_t;
#endif

// Aila–Laine 64-byte BVH node: the boxes of both children live in the parent, so one node fetch
// gives everything the slab tests of a traversal step need.
//   left_xy  = (left.lo.x,  left.hi.x,  left.lo.y,  left.hi.y)
//   right_xy = (right.lo.x, right.hi.x, right.lo.y, right.hi.y)
//   lr_z     = (left.lo.z,  left.hi.z,  right.lo.z, right.hi.z)
//   link     = (left child, right child, parent node (-1 at the root), depth (root = 0))
// A child reference >= 0 is an interior node index; < 0 is a leaf: leaf index = ~reference.
struct BvhNode {
  vec4 left_xy;
  vec4 right_xy;
  vec4 lr_z;
  ivec4 link;
};

// A 4-wide node with quantised child boxes (--bvh-nodes wide4; host/bvh/wide_nodes.h): 64
// bytes like BvhNode, for up to four children, so a traversal step covers about two binary
// levels for the same four texel fetches. Each child box lies on a grid over this node's box:
//   origin    = the node box's low corner
//   exponents = the grid step per axis as a biased float exponent: step = 2^(byte - 127), x in
//               byte 0, y in byte 1, z in byte 2 (byte 3 is 0)
//   child     = child references as BvhNode::link's (>= 0 wide node, < 0 ~leaf); an empty slot
//               holds 0x7fffffff
//   lo, hi    = (x, y, z, 0): byte i of each word is child i's grid coordinate q on that axis;
//               the bound is origin + q × step (shaders/shared/wide_node.h), rounded outward
//               when built, so the decoded box holds the child's exact box.
struct WideNode {
  vec3 origin;
  uint exponents;
  ivec4 child;
  uvec4 lo;
  uvec4 hi;
};

// A 4-wide node with its child boxes as floats (--bvh-nodes wide4-float): 112 bytes, 7 texels;
// the boxes are the binary layout's exactly, so it costs three texel fetches more than a
// WideNode and no decoding. Per axis a, lo_a and hi_a hold the 4 children's bounds (child i in
// component i); child as WideNode::child (an empty slot's box is 0).
struct WideFloatNode {
  vec4 lo_x;
  vec4 hi_x;
  vec4 lo_y;
  vec4 hi_y;
  vec4 lo_z;
  vec4 hi_z;
  ivec4 child;
};

// A leaf: a run of triangle records. parent/depth serve HRPP's go-up level.
struct BvhLeaf {
  uint first_triangle;  // index into the triangle records
  uint triangle_count;  // 0 only for the empty placeholder of a single-leaf tree
  int parent;           // interior node holding this leaf
  uint depth;           // depth of the leaf (root node = 0)
};

// World-space triangle in leaf order, laid out for the watertight test (Woop, Benthin, Wald
// 2013): the vertices plus the triangle's id in the scene's flattened order.
struct TriangleRecord {
  vec3 v0;
  uint prim;  // triangle id (docs/FORMATS.md)
  vec3 v1;
  uint pad0;
  vec3 v2;
  uint pad1;
};

// A ray as in the rays file (32 bytes): origin, tmin, direction, tmax.
struct Ray {
  vec3 origin;
  float tmin;
  vec3 dir;
  float tmax;
};

// A hit as in the hits file (16 bytes). prim = -1: miss. u, v: barycentrics of v1 and v2.
struct Hit {
  int prim;
  float t;
  float u;
  float v;
};

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_GPU_TYPES_H
