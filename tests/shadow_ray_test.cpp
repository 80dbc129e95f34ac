// host/trace/offset_ray.h shadow_ray_to on the CPU reference traversal: a shadow ray from a
// receiver to a point on a parallel emitter close to it never reaches the emitter's own
// triangles (gaps 1e-4..1, the pair translated by 0, 1e2 and 1e4 along (1, 1, 1)), yet reaches
// an occluder between them; where the gap is under the two offsets the ray turns around
// (render_shade.comp drops such rays); a ray to a point light ends 1/8192 of its length short
// of it; p = q gives a NaN direction, a ray that misses.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "trace/cpu_traversal.h"
#include "trace/offset_ray.h"

namespace hrpp {
namespace {

using V = glm::vec3;

void add_quad(Scene& s, V c, V u, V v) {
  for (const Triangle& t : {Triangle{c, c + u, c + u + v}, Triangle{c, c + u + v, c + v}}) {
    s.triangles.push_back(t);
    s.shading.push_back(TriangleShading{});
  }
}

// A square emitter of half-side `gap` (triangles 2 and 3) at `gap` below a 3gap × 3gap receiver
// facing down at y = 0.5, both centred on x = z = 0.3 and moved by shift·(1, 1, 1); with
// `blocker`, a 4 × 4 square halfway between them.
Scene receiver_and_emitter(float gap, float shift, bool blocker) {
  Scene s;
  const V c = V(shift) + V(0.3f, 0.5f, 0.3f);
  add_quad(s, c - V(1.5f * gap, 0, 1.5f * gap), V(3 * gap, 0, 0), V(0, 0, 3 * gap));
  add_quad(s, c - V(gap, gap, gap), V(2 * gap, 0, 0), V(0, 0, 2 * gap));
  if (blocker) add_quad(s, c - V(2.0f, 0.5f * gap, 2.0f), V(4, 0, 0), V(0, 0, 4));
  return s;
}

GpuBvh bvh_of(const Scene& s) { return make_gpu_layout(build_bvh(s, BvhConfig{}), s); }

float offset_distance(V p, V n) { return glm::length(offset_ray_origin(p, n) - p); }

struct PairCounts {
  int pairs = 0, occluded = 0, turned = 0;
};

// Shadow rays from random receiver points (barycentric, as the renderer computes hit points)
// to points on the emitter sampled as render_shade.comp samples them, its corners included.
PairCounts trace_pairs(const Scene& s, const GpuBvh& bvh) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const V down(0, -1, 0), up(0, 1, 0);
  PairCounts counts;
  for (int i = 0; i < 400; ++i) {
    const Triangle& r = s.triangles[i % 2];
    const Triangle& l = s.triangles[2 + i / 2 % 2];
    const float a = u01(rng), b = u01(rng);
    const V p = barycentric_point(r, a, (1.0f - a) * b);
    const float u1 = i < 8 ? 1.0f : u01(rng), u2 = i < 8 ? float(i / 4) : u01(rng);
    const float root = std::sqrt(u1);
    const V q = l.v0 + root * (1.0f - u2) * (l.v1 - l.v0) + root * u2 * (l.v2 - l.v0);
    const gpu::Ray ray = shadow_ray_to(p, down, q, up);
    ++counts.pairs;
    if (!(glm::dot(ray.dir, q - p) > 0.0f)) ++counts.turned;
    else if (trace_any(bvh, ray)) ++counts.occluded;
  }
  return counts;
}

// Tested where the gap is at least twice the two offsets (at 1e4 a gap under 1 is within 1024
// ULPs of the coordinates: not resolvable by offsetting).
TEST(ShadowRay, NeverReachesTheEmittersOwnSurface) {
  for (float gap : {1e-4f, 1e-3f, 1e-2f, 1e-1f, 1.0f})
    for (float shift : {0.0f, 1e2f, 1e4f}) {
      const Scene open = receiver_and_emitter(gap, shift, false);
      const V p = open.triangles[0].v0;
      const float offsets = offset_distance(p, V(0, -1, 0)) +
                            offset_distance(p - V(0, gap, 0), V(0, 1, 0));
      if (gap < 2.0f * offsets) continue;
      const PairCounts free = trace_pairs(open, bvh_of(open));
      const Scene closed = receiver_and_emitter(gap, shift, true);
      const PairCounts blocked = trace_pairs(closed, bvh_of(closed));
      EXPECT_EQ(free.occluded, 0) << "gap " << gap << " shift " << shift;
      EXPECT_EQ(free.turned, 0) << "gap " << gap << " shift " << shift;
      EXPECT_EQ(blocked.occluded, blocked.pairs) << "gap " << gap << " shift " << shift;
    }
}

// A gap under the two offsets: the moved ends cross and the ray points away from the light.
TEST(ShadowRay, TurnsAroundWhenTheOffsetsCross) {
  const V p(100.3f, 100.5f, 100.3f), q = p - V(0.0f, 1e-3f, 0.0f);  // offsets: 2 × 2e-3
  const gpu::Ray ray = shadow_ray_to(p, V(0, -1, 0), q, V(0, 1, 0));
  EXPECT_LT(glm::dot(ray.dir, q - p), 0.0f);
}

TEST(ShadowRay, EndsJustShortOfAPointLight) {
  for (float shift : {0.0f, 1e2f, 1e4f})
    for (float d : {1e-2f, 1.0f, 1e2f}) {
      const V p = V(shift) + V(0.3f, 0.0f, 0.3f), light = p + V(0.0f, d, 0.0f);
      if (d < 2.0f * offset_distance(p, V(0, 1, 0))) continue;  // 1e-2 at 1e4: 0.25 offset
      const gpu::Ray ray = shadow_ray_to(p, V(0, 1, 0), light, V(0.0f));
      const V end = ray.origin + ray.dir * ray.tmax;
      const float len = glm::length(light - ray.origin);
      const float slack = 8.0f * std::nextafter(std::fabs(light.y), 1e38f) -
                          8.0f * std::fabs(light.y);  // 8 ULPs of the light's coordinates
      EXPECT_EQ(ray.origin, offset_ray_origin(p, V(0, 1, 0)));
      EXPECT_NEAR(glm::length(light - end), len / 8192.0f, slack + len * 1e-6f)
          << "d " << d << " shift " << shift;
      EXPECT_GT(glm::dot(ray.dir, light - p), 0.0f);
    }
}

TEST(ShadowRay, ZeroLengthMisses) {
  Scene s = receiver_and_emitter(0.1f, 0.0f, false);
  const V p(0.3f, 0.5f, 0.3f);
  const gpu::Ray ray = shadow_ray_to(p, V(0.0f), p, V(0.0f));
  EXPECT_TRUE(std::isnan(ray.dir.x) && std::isnan(ray.dir.y) && std::isnan(ray.dir.z));
  EXPECT_FALSE(trace_any(bvh_of(s), ray));
}

}  // namespace
}  // namespace hrpp
