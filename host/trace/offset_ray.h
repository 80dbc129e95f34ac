// Origins of secondary rays, moved off the surface they leave so the new ray cannot hit that
// surface again at t ≈ 0 (self-intersection, "shadow acne"). Wächter and Binder, "A Fast and
// Robust Method for Avoiding Self-Intersection", Ray Tracing Gems (2019), chapter 6.
//
// The point is moved along the normal by a fixed number of units in the last place (ULPs) of
// each coordinate: the error of a computed hit point grows with the magnitude of its
// coordinates, and so does the offset. Near the origin, where a few ULPs are vanishingly small,
// a small fixed distance is added instead. Use it with tmin = 0 on the new ray.
//
// Reused by every stage that spawns secondary rays (AO, diffuse, shadow, path continuation).
// Shadow rays toward a point on a light move both ends (shadow_ray_to). The GLSL side
// (shaders/lib/offset_ray.glsl) mirrors it operation for operation.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "gpu_types.h"
#include "scene/scene.h"

namespace hrpp {

// The constants of the chapter (tuned there for scenes of roughly unit to thousand-unit scale).
inline constexpr float kOffsetOrigin = 1.0f / 32.0f;       // below this |coordinate|: float offset
inline constexpr float kOffsetFloatScale = 1.0f / 65536.0f;  // float offset per unit normal
inline constexpr float kOffsetIntScale = 256.0f;           // ULPs per unit normal

// p: the hit point (best computed from barycentrics, not origin + t·dir); n: the geometric
// normal on the side the new ray leaves into (not necessarily unit, but the constants assume
// |n| ≈ 1). Returns p moved off the surface towards n.
inline glm::vec3 offset_ray_origin(const glm::vec3& p, const glm::vec3& n) {
  glm::vec3 out;
  for (int i = 0; i < 3; ++i) {
    const auto of_i = static_cast<std::int32_t>(kOffsetIntScale * n[i]);
    const auto bits = std::bit_cast<std::uint32_t>(p[i]);
    // Moving the bit pattern of a negative float up makes it more negative: flip the sign of
    // the step so the point always moves in the direction of n. Unsigned arithmetic wraps like
    // the GLSL int does (-0.0 is INT32_MIN as an int: a signed step below it would be undefined
    // behaviour in C++; its result is unused, |p| < kOffsetOrigin, but UBSan stops on it).
    const auto step = static_cast<std::uint32_t>(p[i] < 0.0f ? -of_i : of_i);
    const float p_i = std::bit_cast<float>(bits + step);
    out[i] = std::fabs(p[i]) < kOffsetOrigin ? p[i] + kOffsetFloatScale * n[i] : p_i;
  }
  return out;
}

// Shadow rays are 1/8192 of their length short of the (moved) light point: exact in float.
inline constexpr float kShadowRayLength = 1.0f - 1.0f / 8192.0f;

// Shadow ray from p (on a surface; n: the side the ray leaves into) to q on a light (nq: the
// light surface's unit normal on p's side; zero for a point light, which leaves q in place).
// As pbrt's SpawnRayTo: both ends are moved off their surfaces and the direction and tmax come
// from the moved points, so the ray stops short of the light's own surface however close p is
// to it (as long as the two offsets do not cross). Zero length: NaN direction, a ray that misses.
inline gpu::Ray shadow_ray_to(const glm::vec3& p, const glm::vec3& n, const glm::vec3& q,
                              const glm::vec3& nq) {
  const glm::vec3 o = offset_ray_origin(p, n);
  const glm::vec3 d = offset_ray_origin(q, nq) - o;
  const float len = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  const glm::vec3 dir(d.x / len, d.y / len, d.z / len);
  return gpu::Ray{o, 0.0f, dir, len * kShadowRayLength};
}

// Point on triangle tri at barycentrics (u, v) of v1 and v2 (the hit record of docs/FORMATS.md).
inline glm::vec3 barycentric_point(const Triangle& tri, float u, float v) {
  return (1.0f - u - v) * tri.v0 + u * tri.v1 + v * tri.v2;
}

// Unit geometric normal of tri turned to face against `incoming` (the direction of the ray that
// hit it), i.e. onto the side the incoming ray came from. Zero for a degenerate triangle.
inline glm::vec3 facing_normal(const Triangle& tri, const glm::vec3& incoming) {
  const glm::vec3 c = glm::cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
  const float len = glm::length(c);
  if (!(len > 0.0f)) return glm::vec3(0.0f);
  const glm::vec3 n = c / len;
  return glm::dot(n, incoming) > 0.0f ? -n : n;
}

}  // namespace hrpp
