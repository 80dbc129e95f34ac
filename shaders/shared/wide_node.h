// A WideNode's child boxes decoded (shaders/shared/gpu_types.h): one definition for the trace
// kernels (shaders/lib/traversal.glsl) and for the host, whose builder rounds every box outward
// with this same decoding (host/bvh/wide_nodes.cpp), so the box a kernel tests always holds the
// child's exact box.
#ifndef HRPP_WIDE_NODE_H
#define HRPP_WIDE_NODE_H

#include "glsl_cpp.h"
#include "gpu_types.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

#define HRPP_WIDE_CHILDREN 4
// A WideNode's empty child slot (the traversal's stack sentinel: never a node).
#define HRPP_WIDE_EMPTY_SLOT 0x7fffffff
// The biased exponents a grid step may have: 2^-126 (the smallest normal float) to 2^120
// (255 steps, the largest coordinate, stay finite).
#define HRPP_WIDE_EXPONENT_MIN 1u
#define HRPP_WIDE_EXPONENT_MAX 247u

// The grid step on `axis` (0: x, 1: y, 2: z): 2^(exponent byte - 127).
HRPP_INLINE float hrpp_grid_step(uint exponents, uint axis) {
  return uintBitsToFloat(((exponents >> (8u * axis)) & 0xFFu) << 23u);
}

// Child `child`'s grid coordinate (0..255) in a word of WideNode::lo or ::hi.
HRPP_INLINE uint hrpp_grid_coordinate(uint word, uint child) {
  return (word >> (8u * child)) & 0xFFu;
}

// The bound at grid coordinate q: q × step is exact (8 bits times a normal power of two), so
// the bound is the sum rounded once, fused or not.
HRPP_INLINE float hrpp_grid_bound(float origin, float step, uint q) {
  return origin + float(q) * step;
}

// A node's grid steps (x, y, z), decoded once for its four children.
HRPP_INLINE vec3 hrpp_grid_steps(WideNode n) {
  return vec3(hrpp_grid_step(n.exponents, 0u), hrpp_grid_step(n.exponents, 1u),
              hrpp_grid_step(n.exponents, 2u));
}

// Child `child`'s box as the traversal tests it (`steps`: hrpp_grid_steps(n)).
HRPP_INLINE void hrpp_wide_child_box(WideNode n, vec3 steps, uint child, HRPP_OUT(vec3) lo,
                                     HRPP_OUT(vec3) hi) {
  lo = vec3(hrpp_grid_bound(n.origin.x, steps.x, hrpp_grid_coordinate(n.lo.x, child)),
            hrpp_grid_bound(n.origin.y, steps.y, hrpp_grid_coordinate(n.lo.y, child)),
            hrpp_grid_bound(n.origin.z, steps.z, hrpp_grid_coordinate(n.lo.z, child)));
  hi = vec3(hrpp_grid_bound(n.origin.x, steps.x, hrpp_grid_coordinate(n.hi.x, child)),
            hrpp_grid_bound(n.origin.y, steps.y, hrpp_grid_coordinate(n.hi.y, child)),
            hrpp_grid_bound(n.origin.z, steps.z, hrpp_grid_coordinate(n.hi.z, child)));
}

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_WIDE_NODE_H
