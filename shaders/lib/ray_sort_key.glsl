// The reordering key of a ray (shaders/shared/ray_sort_interface.h): the direction's octant
// above the Morton code of the origin's cell in a grid of 2^HRPP_SORT_CELL_BITS cells per axis
// over the scene bounds. Rays with equal keys start in the same cell and head into the same
// octant. C++ mirror, operation for operation: ray_sort_key() in host/trace/ray_order.cpp.
#ifndef HRPP_RAY_SORT_KEY_GLSL
#define HRPP_RAY_SORT_KEY_GLSL

// The cell of coordinate o on one axis: 0 below the bounds (and for NaN), the last cell above.
uint ray_sort_cell(float o, float lo, float scale) {
  const float last = float((1u << HRPP_SORT_CELL_BITS) - 1u);
  precise const float f = (o - lo) * scale;
  return uint(f >= 0.0 ? min(f, last) : 0.0);
}

uint ray_sort_key(Ray r, vec3 lo, vec3 scale) {
  const uvec3 c = uvec3(ray_sort_cell(r.origin.x, lo.x, scale.x),
                        ray_sort_cell(r.origin.y, lo.y, scale.y),
                        ray_sort_cell(r.origin.z, lo.z, scale.z));
  uint morton = 0u;
  for (uint b = 0u; b < uint(HRPP_SORT_CELL_BITS); ++b)
    morton |= (((c.x >> b) & 1u) << (3u * b)) | (((c.y >> b) & 1u) << (3u * b + 1u)) |
              (((c.z >> b) & 1u) << (3u * b + 2u));
  const uvec3 sign = floatBitsToUint(r.dir) >> 31u;
  const uint octant = sign.x | (sign.y << 1u) | (sign.z << 2u);
  return (octant << (3u * uint(HRPP_SORT_CELL_BITS))) | morton;
}

#endif  // HRPP_RAY_SORT_KEY_GLSL
