// Extreme cases on the CPU reference traversal (host/trace/): closest and any hit on every ray
// group of tests/extreme_cases.h, in every frame (unit, translated by 1e4 and 1e6, scaled by
// 1e-4 and 1e4), judged against the double-precision oracle (tests/double_reference.h, its
// tolerances are explained there), plus exact rules: no ray from inside a closed mesh escapes
// it, and crosses it exactly once (hits of triangles sharing the crossed edge or vertex have one
// t); vertical rays never fall through the floor's shared edges and vertices; secondary rays
// leaving a surface at grazing angles never hit it again; NaN/Inf/zero rays miss; no box hides a
// hit of the triangle test (hidden_hits). Brute force may pick another triangle on rays the
// oracle calls either way (see below); counted, printed. The leak suite (LeakRays) does the
// same for closed meshes of thousands of triangles translated up to 1e6.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "double_reference.h"
#include "extreme_cases.h"
#include "trace/brute_force.h"
#include "trace/cpu_traversal.h"
#include "trace/ray_setup.h"
#include "trace/slab_test.h"
#include "trace/watertight.h"

namespace hrpp {
namespace {

using test::RayGroup;

// Distinct crossings of a ray with triangles [first, last): every triangle the float test hits,
// their t values clustered (a crossing through a shared edge or vertex hits each triangle there
// at the same t, up to rounding).
int crossings(const Scene& s, const gpu::Ray& ray, int first, int last) {
  const RaySetup r = setup_ray(ray);
  std::vector<float> ts;
  for (int i = first; i < last; ++i) {
    TriangleHit h{};
    const Triangle& t = s.triangles[i];
    if (intersect_triangle(r, t.v0, t.v1, t.v2, ray.tmax, &h)) ts.push_back(h.t);
  }
  std::sort(ts.begin(), ts.end());
  int n = 0;
  for (std::size_t i = 0; i < ts.size(); ++i)
    if (i == 0 || ts[i] - ts[i - 1] > 1e-4f * std::max(1.0f, std::abs(ts[i]))) ++n;
  return n;
}

// Hits the traversal cannot reach: triangles the watertight test hits within the ray's
// [tmin, tmax] that lie under a box failing the slab test (with the ray's tmax) on the way from
// the root. The slab test must be conservative with respect to the triangle test, not only the
// exact ray: where this is 0, the traversal misses only rays brute force misses, so no closed
// mesh leaks through the BVH. (Culling against the best hit so far is another matter: see
// docs/TESTING.md, "Known float32 limits".)
int hidden_hits(const GpuBvh& bvh, const gpu::Ray& ray) {
  const RaySetup r = setup_ray(ray);
  if (!r.valid) return 0;
  int hidden = 0;
  std::vector<std::pair<int, bool>> todo{{0, true}};  // child reference, every box passed
  while (!todo.empty()) {
    const auto [ref, reached] = todo.back();
    todo.pop_back();
    if (is_leaf_ref(ref)) {
      if (reached) continue;
      const gpu::BvhLeaf& leaf = bvh.leaves[leaf_index(ref)];
      for (gpu::uint i = leaf.first_triangle; i < leaf.first_triangle + leaf.triangle_count; ++i) {
        const gpu::TriangleRecord& t = bvh.triangles[i];
        TriangleHit h{};
        hidden += intersect_triangle(r, t.v0, t.v1, t.v2, ray.tmax, &h);
      }
      continue;
    }
    const gpu::BvhNode& n = bvh.nodes[ref];
    float t = 0.0f;
    todo.push_back({n.link.x, reached && slab_test(r, {n.left_xy.x, n.left_xy.z, n.lr_z.x},
                                                  {n.left_xy.y, n.left_xy.w, n.lr_z.y},
                                                  ray.tmax, &t)});
    todo.push_back({n.link.y, reached && slab_test(r, {n.right_xy.x, n.right_xy.z, n.lr_z.z},
                                                  {n.right_xy.y, n.right_xy.w, n.lr_z.w},
                                                  ray.tmax, &t)});
  }
  return hidden;
}

class ExtremeRays : public testing::TestWithParam<test::Frame> {
 protected:
  void check(bool huge);
};

void ExtremeRays::check(bool huge) {
  const test::ExtremeScene x = test::make_extreme_scene(GetParam(), huge);
  const GpuBvh bvh = make_gpu_layout(build_bvh(x.scene), x.scene);
  const std::string name = GetParam().name + (huge ? "+huge" : "");
  for (const RayGroup& g : x.groups) {
    int oracle_fails = 0, brute_differs = 0, rule_fails = 0, hits = 0, crossing_fails = 0,
        hidden = 0;
    for (const gpu::Ray& ray : g.rays) {
      const gpu::Hit h = trace_closest(bvh, ray);
      const bool occluded = trace_any(bvh, ray);
      hits += h.prim >= 0;
      // Brute force with the same float tests gives the same answer except on rays the oracle
      // calls either way (counted, printed): a box whose hit lies within the triangle test's t
      // error of the best t so far can be culled (docs/TESTING.md, "Known float32 limits").
      // Both answers are within the oracle's tolerance: checked below for the traversal's
      // answer. No box hides a hit from the ray's [tmin, tmax] itself (hidden_hits).
      const gpu::Hit b = brute_force_closest(x.scene, ray);
      hidden += hidden_hits(bvh, ray);
      if (b.prim != h.prim || (h.prim >= 0 && b.t != h.t)) ++brute_differs;
      EXPECT_EQ(occluded, h.prim >= 0) << g.name;
      const std::string why = test::judge_closest(x.scene, ray, h);
      const std::string why_any = test::judge_any(x.scene, ray, occluded);
      if (!why.empty() || !why_any.empty()) {
        if (++oracle_fails <= 5) ADD_FAILURE() << g.name << ": " << why << why_any;
      }
      const bool in_range = h.prim >= g.first && h.prim < g.last;
      if (!huge && ((g.rule == RayGroup::Rule::kHitRange && !in_range) ||
                    (g.rule == RayGroup::Rule::kAvoidRange && in_range))) {
        if (++rule_fails <= 5)
          ADD_FAILURE() << g.name << ": ray o=(" << ray.origin.x << "," << ray.origin.y << ","
                        << ray.origin.z << ") d=(" << ray.dir.x << "," << ray.dir.y << ","
                        << ray.dir.z << ") hit " << h.prim << " t=" << h.t;
      }
      // From inside a closed convex mesh: exactly one crossing of it.
      if (!huge && g.name.rfind("inside_", 0) == 0 && crossings(x.scene, ray, g.first, g.last) != 1)
        ++crossing_fails;
    }
    EXPECT_EQ(oracle_fails, 0) << name << " " << g.name;
    EXPECT_EQ(rule_fails, 0) << name << " " << g.name << " (escapes / fall-throughs / self-hits)";
    EXPECT_EQ(crossing_fails, 0) << name << " " << g.name << " (crossings != 1)";
    // With the huge triangle, every hidden hit is on it: rays moving away from it (exact t
    // < 0) that the float test hits at t ≈ 0, within its error bound. Counted, printed.
    if (!huge) {
      EXPECT_EQ(hidden, 0) << name << " " << g.name << " (hits hidden by a box)";
    }
    std::printf(
        "%-20s %-15s %5zu rays %5d hits, oracle fails %d, rule fails %d, hidden hits %d, "
        "brute force differs (both right) %d\n",
        name.c_str(), g.name.c_str(), g.rays.size(), hits, oracle_fails, rule_fails, hidden,
        brute_differs);
  }
  // Invalid rays miss and are free (defined result, no hang).
  for (const gpu::Ray& r :
       test::invalid_rays(x.scene.triangles[0].v0 * 0.0f + bvh.bounds.center())) {
    EXPECT_EQ(trace_closest(bvh, r).prim, -1);
    EXPECT_FALSE(trace_any(bvh, r));
  }
}

TEST_P(ExtremeRays, CpuReferenceAgainstDoubleOracleAndExactRules) { check(false); }
TEST_P(ExtremeRays, WithAHugeTriangleAgainstDoubleOracle) { check(true); }

INSTANTIATE_TEST_SUITE_P(Frames, ExtremeRays, testing::ValuesIn(test::extreme_frames()),
                         test::frame_param_name<testing::TestParamInfo<test::Frame>>);

// Leak suite (tests/extreme_cases.h): no ray from inside either closed mesh escapes it, closest
// or any hit; every kOracleStride-th closest hit is judged by the double oracle too, and every
// kHiddenStride-th ray (every kOnFaceHiddenStride-th of box_on_face) has no hit hidden by a
// box (all of them would take minutes: both test every triangle for every ray).
constexpr std::size_t kOracleStride = 64;
constexpr std::size_t kHiddenStride = 64;
constexpr std::size_t kOnFaceHiddenStride = 16;

class LeakRays : public testing::TestWithParam<test::LeakFrame> {};

std::string describe(const gpu::Ray& r, const gpu::Hit& h) {
  char s[256];
  std::snprintf(s, sizeof s, "o=(%.9g,%.9g,%.9g) d=(%.9g,%.9g,%.9g) hit %d t=%.9g", r.origin.x,
                r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, h.prim, h.t);
  return s;
}

TEST_P(LeakRays, NoRayFromInsideAClosedMeshEscapes) {
  const test::LeakScene x = test::make_leak_scene(GetParam());
  const GpuBvh bvh = make_gpu_layout(build_bvh(x.scene), x.scene);
  for (const RayGroup& g : x.groups) {
    const bool inside = g.rule == RayGroup::Rule::kHitRange;  // else: origins on the surface
    const std::size_t hidden_stride = inside ? kHiddenStride : kOnFaceHiddenStride;
    int escapes = 0, any_escapes = 0, oracle_fails = 0, hidden = 0;
    for (std::size_t i = 0; i < g.rays.size(); ++i) {
      const gpu::Ray& ray = g.rays[i];
      const gpu::Hit h = trace_closest(bvh, ray);
      if (inside && (h.prim < g.first || h.prim >= g.last)) {
        if (++escapes <= 3) ADD_FAILURE() << g.name << " escape: " << describe(ray, h);
      }
      any_escapes += inside && !trace_any(bvh, ray);
      if (i % hidden_stride == 0) hidden += hidden_hits(bvh, ray);
      if (i % kOracleStride != 0) continue;
      const std::string why = test::judge_closest(x.scene, ray, h);
      if (!why.empty() && ++oracle_fails <= 3) ADD_FAILURE() << g.name << ": " << why;
    }
    EXPECT_EQ(escapes, 0) << GetParam().name << " " << g.name;
    EXPECT_EQ(any_escapes, 0) << GetParam().name << " " << g.name << " (any hit)";
    EXPECT_EQ(oracle_fails, 0) << GetParam().name << " " << g.name;
    EXPECT_EQ(hidden, 0) << GetParam().name << " " << g.name << " (hits hidden by a box)";
    std::printf(
        "%-15s %-19s %6zu rays: escapes %d (any hit %d), oracle fails %d of %zu, hidden hits "
        "%d of %zu rays\n",
        GetParam().name.c_str(), g.name.c_str(), g.rays.size(), escapes, any_escapes,
        oracle_fails, (g.rays.size() + kOracleStride - 1) / kOracleStride, hidden,
        (g.rays.size() + hidden_stride - 1) / hidden_stride);
  }
}

INSTANTIATE_TEST_SUITE_P(Frames, LeakRays, testing::ValuesIn(test::leak_frames()),
                         [](const testing::TestParamInfo<test::LeakFrame>& i) {
                           return i.param.name;
                         });

// Triangles up to 4e18 across (edge functions ~1e37) give a finite t: formed from the
// normalised barycentrics, not as (U·az + V·bz + W·cz)/det, which overflowed to +Inf (1e17
// across at distance 1e4). From ~1e19 the edge functions themselves overflow (|v − o|² past
// FLT_MAX): a miss, never a hit at a NaN or infinite t.
TEST(HugeTriangles, FiniteTUpTo4e18AcrossAndMissesBeyond) {
  const float inf = std::numeric_limits<float>::infinity();
  for (const float h : {1e14f, 1e17f, 1e18f, 4e18f, 2e19f})
    for (const float dist : {20.0f, 1e4f}) {
      const gpu::Ray ray{{0.3f, 0.2f, 0.0f}, 0.0f, {0.01f, -0.02f, -1.0f}, inf};
      TriangleHit hit{};
      const bool got = intersect_triangle(setup_ray(ray), {-h, -h, -dist}, {h, -h, -dist},
                                          {0.0f, h, -dist}, inf, &hit);
      if (h > 1e19f) {
        EXPECT_FALSE(got) << h;
        continue;
      }
      ASSERT_TRUE(got) << h << " " << dist;
      EXPECT_NEAR(hit.t, dist, 1e-5f * dist) << h;
      const Triangle t{{-h, -h, -dist}, {h, -h, -dist}, {0.0f, h, -dist}};
      const test::OracleHit o = test::oracle_triangle(t, ray);
      EXPECT_LE(std::abs(hit.t - o.t), o.t_tol) << h << " " << dist;
    }
}

// The oracle itself: a certain hit, a certain miss, an edge (either), a degenerate triangle.
TEST(DoubleOracle, JudgesClearCasesAndToleratesEdges) {
  const Triangle t{{-1, -1, 5}, {1, -1, 5}, {0, 1, 5}};
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(test::oracle_triangle(t, {{0, 0, 0}, 0, {0, 0, 1}, inf}).verdict, test::Verdict::kHit);
  EXPECT_DOUBLE_EQ(test::oracle_triangle(t, {{0, 0, 0}, 0, {0, 0, 1}, inf}).t, 5.0);
  EXPECT_EQ(test::oracle_triangle(t, {{3, 0, 0}, 0, {0, 0, 1}, inf}).verdict, test::Verdict::kMiss);
  EXPECT_EQ(test::oracle_triangle(t, {{0, -1, 0}, 0, {0, 0, 1}, inf}).verdict,
            test::Verdict::kEither);
  EXPECT_EQ(test::oracle_triangle(t, {{0, 0, 0}, 0, {0, 0, 1}, 4.0f}).verdict,
            test::Verdict::kMiss);
  EXPECT_EQ(test::oracle_triangle({{0, 0, 5}, {1, 1, 5}, {2, 2, 5}}, {{1, 1, 0}, 0, {0, 0, 1}, inf})
                .verdict,
            test::Verdict::kMiss);
  Scene s;
  s.triangles = {t};
  // A wrong float answer is caught: a hit at the wrong t, a miss of a certain hit.
  EXPECT_FALSE(test::judge_closest(s, {{0, 0, 0}, 0, {0, 0, 1}, inf}, {0, 5.01f, 0, 0}).empty());
  EXPECT_FALSE(test::judge_closest(s, {{0, 0, 0}, 0, {0, 0, 1}, inf}, {-1, 0, 0, 0}).empty());
  EXPECT_TRUE(
      test::judge_closest(s, {{0, 0, 0}, 0, {0, 0, 1}, inf}, {0, 5.0f, 0.25f, 0.5f}).empty());
}

}  // namespace
}  // namespace hrpp
