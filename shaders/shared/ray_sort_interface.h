// Interface of the ray reordering kernels (shaders/ray_sort_*.comp): a stable LSD radix sort of
// the rays by a key that puts similar rays next to each other (direction octant and the Morton
// code of the origin's cell in the scene bounds). Its result is the order, a ray index list that
// the indexed trace kernels read (shaders/lib/trace_kernel.glsl); a gather that copies the rays
// to their sorted places is optional. Host side: host/gpu/ray_sorter.h; CPU ground truth:
// host/trace/ray_order.h. One definition; the host static_asserts the sizes.
#ifndef HRPP_RAY_SORT_INTERFACE_H
#define HRPP_RAY_SORT_INTERFACE_H

#include "gpu_types.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

#define HRPP_SORT_WORKGROUP_SIZE 64
#define HRPP_SORT_SCAN_WORKGROUP_SIZE 256

// The key: Morton code of the origin's cell (HRPP_SORT_CELL_BITS bits per axis, a grid of
// 2^bits cells per axis over the scene bounds) below the direction's octant (3 sign bits).
#define HRPP_SORT_CELL_BITS 4
#define HRPP_SORT_KEY_BITS (3 * HRPP_SORT_CELL_BITS + 3)
// Radix passes of HRPP_SORT_DIGIT_BITS bits each, least significant digit first.
#define HRPP_SORT_DIGIT_BITS 8
#define HRPP_SORT_BINS 256
#define HRPP_SORT_PASSES 2
// At most this many blocks (one invocation each) per pass: the scan's loops stay far inside
// lavapipe's loop limiter (docs/DEVICES.md, "Loop limiter").
#define HRPP_SORT_MAX_BLOCKS 1024
#define HRPP_SORT_MIN_BLOCK_ITEMS 64

// Bindings shared by every sort kernel (each uses what it needs).
#define HRPP_SORT_BINDING_RAYS 0         // uniform texel buffer: the rays in queue order
#define HRPP_SORT_BINDING_ITEMS 1        // uvec2 (key, source index), two halves (ping-pong)
#define HRPP_SORT_BINDING_COUNTS 2       // per (digit, block) counts, then their prefix sums
#define HRPP_SORT_BINDING_ORDER 3        // uint per sorted position: the queue index of its ray
#define HRPP_SORT_BINDING_SORTED_RAYS 4  // storage texel buffer: the gather's sorted rays
#define HRPP_SORT_BINDING_COUNT 5

struct RaySortPushConstants {
  vec4 lo;       // xyz: the scene bounds' low corner
  vec4 scale;    // xyz: cells per unit length on each axis (0 on a flat axis)
  uint count;    // rays to sort
  uint block_items;  // items per block (one invocation of count and scatter)
  uint blocks;   // blocks of this sort
  uint shift;    // the pass's digit: (key >> shift) & (HRPP_SORT_BINS - 1)
  uint src;      // first item of the pass's input half of ITEMS
  uint dst;      // first item of its output half (the last pass writes ORDER instead)
  uint pad1;
  uint pad2;
};

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_RAY_SORT_INTERFACE_H
