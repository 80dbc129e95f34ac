// Wächter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing
// Gems (2019), ch. 6, and shadow rays offset at both ends (pbrt's SpawnRayTo): the GLSL mirror
// of host/trace/offset_ray.h, operation for operation (`precise` where a fused multiply-add
// could round differently).
#ifndef HRPP_OFFSET_RAY_GLSL
#define HRPP_OFFSET_RAY_GLSL

#include "gpu_types.h"
#include "ieee_math.glsl"

const float kOffsetOrigin = 1.0 / 32.0;
const float kOffsetFloatScale = 1.0 / 65536.0;
const float kOffsetIntScale = 256.0;

// p moved off its surface towards n (the side the new ray leaves into); use tmin = 0.
vec3 offset_ray_origin(vec3 p, vec3 n) {
  const ivec3 of_i = ivec3(kOffsetIntScale * n);
  const ivec3 bits = floatBitsToInt(p);
  const vec3 p_i = intBitsToFloat(bits + ivec3(p.x < 0.0 ? -of_i.x : of_i.x,
                                               p.y < 0.0 ? -of_i.y : of_i.y,
                                               p.z < 0.0 ? -of_i.z : of_i.z));
  precise vec3 p_f = p + kOffsetFloatScale * n;  // precise: no fused multiply-add, as C++
  return vec3(abs(p.x) < kOffsetOrigin ? p_f.x : p_i.x, abs(p.y) < kOffsetOrigin ? p_f.y : p_i.y,
              abs(p.z) < kOffsetOrigin ? p_f.z : p_i.z);
}

const float kShadowRayLength = 1.0 - 1.0 / 8192.0;

// Shadow ray from p (on a surface, n on the side the ray leaves into) to q on a light (nq: the
// light surface's unit normal on p's side; zero for a point light, which leaves q in place).
// Both ends are moved off their surfaces, and the direction and tmax come from the moved
// points, tmax 1/8192 of the length short of the moved q: the ray cannot reach the light's own
// surface, however close p is to it. Zero length: the direction is NaN and the ray misses.
Ray shadow_ray_to(vec3 p, vec3 n, vec3 q, vec3 nq) {
  const vec3 o = offset_ray_origin(p, n);
  precise vec3 d = offset_ray_origin(q, nq) - o;
  precise float len = ieee_sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  precise vec3 dir = vec3(ieee_div(d.x, len), ieee_div(d.y, len), ieee_div(d.z, len));
  precise float tmax = len * kShadowRayLength;
  return Ray(o, 0.0, dir, tmax);
}

#endif  // HRPP_OFFSET_RAY_GLSL
