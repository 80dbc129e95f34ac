// Body of the ray-query kernels: trace_rayquery_closest.comp (HRPP_ANY_HIT 0) and
// trace_rayquery_any.comp (HRPP_ANY_HIT 1). The driver's traversal (GL_EXT_ray_query) over its
// acceleration structure (host/vk/acceleration_structure.h) answers each ray, one per
// invocation at a time, with the BVH kernels' rules (host/trace/cpu_traversal.h): a hit needs
// tmin <= t <= tmax, both faces count, and a ray with a NaN or infinite origin or direction, a
// zero direction, a NaN tmin or tmax, or tmin > tmax misses without a query. Closest hits break
// ties as the driver does (the BVH kernels: to the lower id). Vulkan requires 0 <= tmin: the
// host refuses rays with a negative tmin (RayQueryTracer::trace), and a resident ray's is
// raised to 0. Counters: rays and hits (the driver's node work is invisible); every ray proves
// it finished with the loop-limiter probe, as the BVH kernels do.
#ifndef HRPP_RAY_QUERY_KERNEL_GLSL
#define HRPP_RAY_QUERY_KERNEL_GLSL

#include "trace_interface.h"

layout(local_size_x = HRPP_TRACE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(set = 0, binding = HRPP_RAY_QUERY_BINDING_SCENE) uniform accelerationStructureEXT scene;
layout(set = 0, binding = HRPP_RAY_QUERY_BINDING_HITS, rgba32ui) uniform writeonly restrict
    uimageBuffer hit_texels;
layout(push_constant) uniform PushConstants { TracePushConstants pc; };

#define HRPP_RAYS_BINDING HRPP_RAY_QUERY_BINDING_RAYS
#include "ray_fetch.glsl"
#define HRPP_COUNTERS_BINDING HRPP_RAY_QUERY_BINDING_COUNTERS
#include "trace_counters.glsl"
#include "loop_limiter.glsl"

bool is_finite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

// False for the rays the BVH kernels never let hit (host/trace/ray_setup.h, RaySetup::valid)
// and for an empty interval.
bool traceable(Ray r) {
  return is_finite(r.origin) && is_finite(r.dir) && any(notEqual(r.dir, vec3(0.0))) &&
         !isnan(r.tmin) && !isnan(r.tmax) && max(r.tmin, 0.0) <= r.tmax;
}

Hit query(Ray r) {
  Hit h = Hit(-1, 0.0, 0.0, 0.0);
  if (!traceable(r)) return h;
  const uint flags = gl_RayFlagsOpaqueEXT | (HRPP_ANY_HIT != 0 ? gl_RayFlagsTerminateOnFirstHitEXT
                                                               : gl_RayFlagsNoneEXT);
  rayQueryEXT q;
  rayQueryInitializeEXT(q, scene, flags, 0xFFu, r.origin, max(r.tmin, 0.0), r.dir, r.tmax);
  while (rayQueryProceedEXT(q)) {
  }
  if (rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
    const vec2 uv = rayQueryGetIntersectionBarycentricsEXT(q, true);
    h = Hit(rayQueryGetIntersectionPrimitiveIndexEXT(q, true),
            rayQueryGetIntersectionTEXT(q, true), uv.x, uv.y);
  }
  return h;
}

// Persistent invocations as in trace_kernel.glsl: one lane per subgroup takes the next rays with
// atomicAdd on the counters' cursor (fetch_position), at most pc.rays_per_invocation per
// invocation (lavapipe's loop limiter counts the driver's traversal loops too).
void main() {
  uint done = 0u, hit_count = 0u, aborted = 0u;
  for (uint k = 0u; k < pc.rays_per_invocation; ++k) {
    bool more;
    const uint index = fetch_position(more);
    if (!more) break;  // uniform across the subgroup
    if (index >= counters.ray_count) continue;
    const Hit h = query(load_ray(index));
    if (loop_budget_left()) {
      imageStore(hit_texels, int(index),
                 uvec4(uint(h.prim), floatBitsToUint(h.t), floatBitsToUint(h.u),
                       floatBitsToUint(h.v)));
      ++done;
      if (h.prim >= 0) ++hit_count;
    } else {
      ++aborted;
    }
  }
  const uint done_sum = subgroupAdd(done), hit_sum = subgroupAdd(hit_count);
  const uint aborted_sum = subgroupAdd(aborted);
  if (subgroupElect()) {
    add_wide(HRPP_COUNTER_RAYS, done_sum);
    add_wide(HRPP_COUNTER_HITS, hit_sum);
    if (aborted_sum != 0u) atomicAdd(counters.aborted, aborted_sum);
  }
}

#endif  // HRPP_RAY_QUERY_KERNEL_GLSL
