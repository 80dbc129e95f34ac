// Wächter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing
// Gems (2019), ch. 6: the GLSL mirror of host/trace/offset_ray.h, operation for operation.
#ifndef HRPP_OFFSET_RAY_GLSL
#define HRPP_OFFSET_RAY_GLSL

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
  return vec3(abs(p.x) < kOffsetOrigin ? p.x + kOffsetFloatScale * n.x : p_i.x,
              abs(p.y) < kOffsetOrigin ? p.y + kOffsetFloatScale * n.y : p_i.y,
              abs(p.z) < kOffsetOrigin ? p.z + kOffsetFloatScale * n.z : p_i.z);
}

#endif  // HRPP_OFFSET_RAY_GLSL
