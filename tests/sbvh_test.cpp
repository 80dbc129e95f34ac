// host/bvh/ spatial splits (--bvh-splits spatial): the triangle chop's boxes hold every point of
// each side and stay inside the triangle's box; SBVH invariants on the stand-in scenes and on
// degenerate inputs (equal, collinear, one triangle, axis-aligned slivers, huge and tiny
// coordinates): every non-degenerate triangle is in a leaf and every point of it is inside a
// leaf box of a leaf that holds it, children inside parents, leaf boxes inside their triangles'
// boxes, bounded duplicates and depth, the same GPU layout on any thread count; the CPU
// reference traversal gives the object-split BVH's closest hits.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/bvh_stats.h"
#include "bvh/gpu_layout.h"
#include "bvh/triangle_clip.h"
#include "common/error.h"
#include "gpu_types.h"
#include "hrpp/prediction_node.h"
#include "scene/load_scene.h"
#include "test_scenes.h"
#include "trace/cpu_traversal.h"
#include "trace/ray_batches.h"

namespace hrpp {
namespace {


bool contains(const Aabb& b, const glm::dvec3& p, double tol) {
  for (int c = 0; c < 3; ++c)
    if (p[c] < static_cast<double>(b.lo[c]) - tol || p[c] > static_cast<double>(b.hi[c]) + tol)
      return false;
  return true;
}

Aabb box_of(const Triangle& t) {
  Aabb b;
  for (const glm::vec3& v : {t.v0, t.v1, t.v2}) b.grow(v);
  return b;
}

// Points of t in double: the vertices, points along the edges and inside, on a 16-step grid.
std::vector<glm::dvec3> sample_points(const Triangle& t) {
  std::vector<glm::dvec3> out;
  constexpr int kSteps = 16;
  for (int i = 0; i <= kSteps; ++i)
    for (int j = 0; i + j <= kSteps; ++j) {
      const double u = static_cast<double>(i) / kSteps, v = static_cast<double>(j) / kSteps;
      out.push_back((1.0 - u - v) * glm::dvec3(t.v0) + u * glm::dvec3(t.v1) + v * glm::dvec3(t.v2));
    }
  return out;
}

// Far below a float step of the triangle's coordinates, far above double rounding.
double tolerance(const Triangle& t) {
  const Aabb b = box_of(t);
  const glm::vec3 m = glm::max(glm::abs(b.lo), glm::abs(b.hi));
  return 1e-12 * std::max({m.x, m.y, m.z});
}

struct LeafInfo {
  Aabb box;
  std::uint32_t first, count;
};

// Walks the tree: children inside parents; returns the leaves and the depth.
std::vector<LeafInfo> walk(const Bvh& bvh, std::uint32_t& max_depth) {
  std::vector<LeafInfo> leaves;
  max_depth = 0;
  if (bvh.nodes.size() == 1) {
    leaves.push_back({bvh.nodes[0].bounds, bvh.nodes[0].first, bvh.nodes[0].count});
    return leaves;
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> stack{{0u, 0u}};
  while (!stack.empty()) {
    const auto [i, depth] = stack.back();
    stack.pop_back();
    const Bvh::Node& n = bvh.nodes[i];
    max_depth = std::max(max_depth, depth);
    if (n.is_leaf()) {
      leaves.push_back({n.bounds, n.first, n.count});
      continue;
    }
    for (std::uint32_t c : {n.first, n.first + 1}) {
      EXPECT_TRUE(n.bounds.contains(bvh.nodes[c].bounds)) << "node " << c << " outside " << i;
      stack.push_back({c, depth + 1});
    }
  }
  return leaves;
}

// Every SBVH invariant (header comment) for `bvh` built from `scene` with `config`.
void expect_valid_sbvh(const Scene& scene, const Bvh& bvh, const BvhConfig& config) {
  std::uint32_t depth = 0;
  const std::vector<LeafInfo> leaves = walk(bvh, depth);
  EXPECT_LT(depth, 64u);
  std::vector<std::vector<Aabb>> boxes_of(scene.triangles.size());
  for (const LeafInfo& l : leaves) {
    EXPECT_LE(l.count, static_cast<std::uint32_t>(config.max_leaf_size));
    Aabb around;  // the union of the leaf's triangles' boxes
    for (std::uint32_t k = l.first; k < l.first + l.count; ++k) {
      const std::uint32_t id = bvh.prim_ids[k];
      ASSERT_LT(id, scene.triangles.size());
      around.grow(box_of(scene.triangles[id]));
      boxes_of[id].push_back(l.box);
    }
    EXPECT_TRUE(around.contains(l.box)) << "leaf box beyond its triangles' boxes";
  }
  std::size_t triangles = 0;
  for (std::size_t id = 0; id < scene.triangles.size(); ++id) {
    const Triangle& t = scene.triangles[id];
    if (is_degenerate(t)) {
      EXPECT_TRUE(boxes_of[id].empty()) << "degenerate triangle " << id << " in a leaf";
      continue;
    }
    ++triangles;
    ASSERT_FALSE(boxes_of[id].empty()) << "triangle " << id << " in no leaf";
    const double tol = tolerance(t);
    int uncovered = 0;
    for (const glm::dvec3& p : sample_points(t))
      uncovered += std::none_of(boxes_of[id].begin(), boxes_of[id].end(),
                                [&](const Aabb& b) { return contains(b, p, tol); });
    EXPECT_EQ(uncovered, 0) << "triangle " << id << ": points outside its leaves' boxes";
  }
  EXPECT_LE(bvh.prim_ids.size(),
            triangles + static_cast<std::size_t>(config.duplicate_budget *
                                                 static_cast<double>(triangles)) + 1);
}

// Builds on 1, 2 and 3 threads: every tree valid, every GPU layout the one-thread one.
Bvh expect_valid_on_any_thread_count(const Scene& scene, BvhConfig config = test::spatial_splits()) {
  config.threads = 1;
  const Bvh one = build_bvh(scene, config);
  expect_valid_sbvh(scene, one, config);
  const GpuBvh g1 = make_gpu_layout(one, scene);
  for (int threads : {2, 3}) {
    config.threads = threads;
    const Bvh other = build_bvh(scene, config);
    expect_valid_sbvh(scene, other, config);
    const GpuBvh g = make_gpu_layout(other, scene);
    EXPECT_EQ(g.nodes.size(), g1.nodes.size()) << threads << " threads";
    EXPECT_EQ(0, std::memcmp(g.nodes.data(), g1.nodes.data(),
                             std::min(g.nodes.size(), g1.nodes.size()) * sizeof(gpu::BvhNode)))
        << threads << " threads";
    EXPECT_EQ(g.triangles.size(), g1.triangles.size()) << threads << " threads";
    int differ = 0;
    for (std::size_t i = 0; i < std::min(g.triangles.size(), g1.triangles.size()); ++i)
      differ += g.triangles[i].prim != g1.triangles[i].prim;
    EXPECT_EQ(differ, 0) << threads << " threads";
  }
  return one;
}

// Random triangles, some long and thin, in [0, scale)^3 + offset.
std::vector<Triangle> random_triangles(int n, unsigned seed, double scale, double offset) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto point = [&] {
    return glm::vec3(glm::dvec3(u(rng), u(rng), u(rng)) * scale + offset);
  };
  std::vector<Triangle> tris;
  for (int i = 0; i < n; ++i) tris.push_back({point(), point(), point()});
  return tris;
}

TEST(TriangleChop, SidesHoldEveryPointAndStayInTheTrianglesBox) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const double scale : {1.0, 1e-30, 1e-38, 1e30, 1e38}) {
    const std::vector<Triangle> tris = random_triangles(300, 17, scale, -0.5 * scale);
    for (const Triangle& t : tris) {
      const Aabb box = box_of(t);
      for (int axis = 0; axis < 3; ++axis) {
        const float plane = static_cast<float>(
            box.lo[axis] + u(rng) * (static_cast<double>(box.hi[axis]) - box.lo[axis]));
        const ChoppedBoxes c = chop_triangle(t, axis, plane);
        ASSERT_FALSE(c.below.empty() && c.above.empty());
        for (const Aabb* side : {&c.below, &c.above}) {
          if (side->empty()) continue;
          EXPECT_TRUE(box.contains(*side)) << "scale " << scale;
        }
        if (!c.below.empty()) {
          EXPECT_LE(c.below.hi[axis], plane);
        }
        if (!c.above.empty()) {
          EXPECT_GE(c.above.lo[axis], plane);
        }
        const double tol = tolerance(t);
        for (const glm::dvec3& p : sample_points(t)) {
          if (p[axis] <= plane) {
            EXPECT_TRUE(contains(c.below, p, tol)) << "scale " << scale;
          }
          if (p[axis] >= plane) {
            EXPECT_TRUE(contains(c.above, p, tol)) << "scale " << scale;
          }
        }
      }
    }
  }
}

TEST(TriangleChop, PlaneThroughAVertexOrAlongAFace) {
  const Triangle t{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  const ChoppedBoxes at_vertex = chop_triangle(t, 0, 2.0f);
  EXPECT_EQ(at_vertex.below.lo, glm::vec3(0, 0, 0));
  EXPECT_EQ(at_vertex.below.hi, glm::vec3(2, 2, 0));
  EXPECT_EQ(at_vertex.above.lo, glm::vec3(2, 0, 0));
  EXPECT_EQ(at_vertex.above.hi, glm::vec3(2, 0, 0));
  const ChoppedBoxes in_plane = chop_triangle(t, 2, 0.0f);  // the whole triangle on both sides
  EXPECT_EQ(in_plane.below.lo, in_plane.above.lo);
  EXPECT_EQ(in_plane.below.hi, in_plane.above.hi);
  const ChoppedBoxes beside = chop_triangle(t, 2, 1.0f);
  EXPECT_TRUE(beside.above.empty());
  // The crossing (1, 1, 0) is widened by its error bound: at most one float step.
  const ChoppedBoxes middle = chop_triangle(t, 0, 1.0f);
  EXPECT_EQ(middle.below.hi, glm::vec3(1, 2, 0));
  EXPECT_EQ(middle.above.lo, glm::vec3(1, 0, 0));
  EXPECT_EQ(middle.above.hi.x, 2.0f);
  EXPECT_GE(middle.above.hi.y, 1.0f);
  EXPECT_LE(middle.above.hi.y, std::nextafter(1.0f, 2.0f));
}

class SbvhScenes : public testing::TestWithParam<std::string> {};

TEST_P(SbvhScenes, InvariantsHoldAndTheCostIsNoWorse) {
  const Scene scene = test::load_test_scene(GetParam());
  const Bvh sbvh = expect_valid_on_any_thread_count(scene);
  const BvhStats object = compute_bvh_stats(build_bvh(scene));
  const BvhStats split = compute_bvh_stats(sbvh);
  std::printf("%s: SAH %.3f object, %.3f spatial; %u references for %u triangles\n",
              GetParam().c_str(), object.sah_cost, split.sah_cost, split.references,
              split.triangles);
  // The builder takes a spatial split only where the SAH says it is cheaper; the greedy
  // estimate is not the tree's cost, so allow a little.
  EXPECT_LE(split.sah_cost, object.sah_cost * 1.01);
}

// With every triangle in one leaf or several, the CPU reference's closest hits are the
// object-split BVH's: the same triangle and t (ties go to the lower id in both).
TEST_P(SbvhScenes, ClosestHitsEqualTheObjectSplitBvhs) {
  const Scene scene = test::load_test_scene(GetParam());
  const GpuBvh object = make_gpu_layout(build_bvh(scene), scene);
  const GpuBvh split = make_gpu_layout(build_bvh(scene, test::spatial_splits()), scene);
  const RayBatches b = test::small_ray_batches(scene, object, 48, 4096);
  int differ = 0;
  for (const std::vector<gpu::Ray>* rays : {&b.primary, &b.ao.rays, &b.diffuse.rays})
    for (const gpu::Ray& r : *rays) {
      const gpu::Hit x = trace_closest(object, r), y = trace_closest(split, r);
      differ += x.prim != y.prim || x.t != y.t || x.u != y.u || x.v != y.v;
      differ += trace_any(object, r) != trace_any(split, r);
    }
  EXPECT_EQ(differ, 0);
}

INSTANTIATE_TEST_SUITE_P(StandIns, SbvhScenes, testing::ValuesIn(test::reference_scene_names()),
                         test::scene_param_name);

TEST(SbvhEdgeCases, OneTriangle) {
  const Scene s = test::synthetic_scene({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
  expect_valid_on_any_thread_count(s);
}

TEST(SbvhEdgeCases, EqualTrianglesAreSplitByMedian) {
  for (const int n : {2, 100, 20000}) {
    const Scene s = test::synthetic_scene(std::vector<Triangle>(n, Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 1}}));
    const Bvh bvh = expect_valid_on_any_thread_count(s);
    EXPECT_EQ(compute_bvh_stats(bvh).max_leaf_size, n == 2 ? 1u : 4u) << n;
  }
}

TEST(SbvhEdgeCases, CollinearAndDegenerateAmongValid) {
  std::vector<Triangle> tris;
  for (int i = 0; i < 3000; ++i) {
    const float f = static_cast<float>(i % 61), g = static_cast<float>(i / 61);
    switch (i % 3) {
      case 0: tris.push_back({{f, g, 0}, {f + 3, g, 0.5f}, {f, g + 2, 1}}); break;       // valid
      case 1: tris.push_back({{f, g, 0}, {f + 1, g + 1, 1}, {f + 2, g + 2, 2}}); break;  // collinear
      default: tris.push_back({{f, g, 0}, {f, g, 0}, {f, g + 1, 0}}); break;             // a segment
    }
  }
  const Scene s = test::synthetic_scene(tris);
  const Bvh bvh = expect_valid_on_any_thread_count(s);
  EXPECT_EQ(bvh.degenerate_count, 2000u);
}

// Long slivers woven in the plane z = 0 (along x and along y) and standing in planes x = const:
// every spatial plane cuts many of them, and the cut parts have no extent on one axis.
TEST(SbvhEdgeCases, AxisAlignedThinTriangles) {
  std::vector<Triangle> tris;
  for (int i = 0; i < 400; ++i) {
    const float f = static_cast<float>(i) * 0.025f;
    tris.push_back({{0, f, 0}, {10, f, 0}, {0, f + 1e-3f, 0}});  // in z = 0, along x
    tris.push_back({{f, 0, 0}, {f, 10, 0}, {f + 1e-3f, 0, 0}});  // in z = 0, along y
    tris.push_back({{f, 0, 0}, {f, 0, 10}, {f, 1e-3f, 0}});      // in x = f, along z
  }
  const Scene s = test::synthetic_scene(tris);
  const Bvh bvh = expect_valid_on_any_thread_count(s);
  EXPECT_GT(bvh.prim_ids.size(), tris.size());  // spatial splits pay here
}

TEST(SbvhEdgeCases, HugeAndTinyCoordinates) {
  for (const double scale : {1e-38, 1e-20, 1e20, 1e36}) {
    std::vector<Triangle> tris = random_triangles(2000, 3, scale, -0.5 * scale);
    const std::vector<Triangle> far = random_triangles(500, 4, 1.0, 1e7);  // big offset, unit size
    tris.insert(tris.end(), far.begin(), far.end());
    const Scene s = test::synthetic_scene(tris);
    expect_valid_on_any_thread_count(s);
  }
}

TEST(SbvhEdgeCases, NoBudgetNoDuplicatesAndAlphaStops) {
  const Scene s = test::synthetic_scene(random_triangles(3000, 9, 1.0, 0.0));
  BvhConfig c = test::spatial_splits();
  c.duplicate_budget = 0.0f;
  const Bvh none = build_bvh(s, c);
  expect_valid_sbvh(s, none, c);
  EXPECT_EQ(none.prim_ids.size(), s.triangles.size());
  c = test::spatial_splits();
  const Bvh some = build_bvh(s, c);
  EXPECT_GT(some.prim_ids.size(), s.triangles.size());  // random triangles overlap a lot
  c.spatial_alpha = 10.0f;  // overlap never exceeds 10 root areas: no spatial split
  EXPECT_EQ(build_bvh(s, c).prim_ids.size(), s.triangles.size());
  c = test::spatial_splits();
  c.unsplit = false;
  expect_valid_sbvh(s, build_bvh(s, c), c);
}

TEST(SbvhEdgeCases, BadBudgetIsAnError) {
  const Scene s = test::synthetic_scene({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
  BvhConfig c = test::spatial_splits();
  c.duplicate_budget = -1.0f;
  EXPECT_THROW(build_bvh(s, c), Error);
}

// A triangle in several leaves predicts from the first of them in leaf order.
TEST(SbvhPrediction, LeafOfPrimIsTheFirstLeafHoldingIt) {
  const Scene s = test::synthetic_scene(random_triangles(2000, 11, 1.0, 0.0));
  const GpuBvh g = make_gpu_layout(build_bvh(s, test::spatial_splits()), s);
  const std::vector<std::uint32_t> leaf = leaf_of_prim(g);
  std::vector<std::uint32_t> first(s.triangles.size(), kNoLeaf);
  std::size_t shared = 0;
  for (std::uint32_t l = 0; l < g.leaves.size(); ++l)
    for (std::uint32_t i = 0; i < g.leaves[l].triangle_count; ++i) {
      const std::uint32_t prim = g.triangles[g.leaves[l].first_triangle + i].prim;
      if (first[prim] == kNoLeaf)
        first[prim] = l;
      else
        ++shared;
    }
  EXPECT_GT(shared, 0u);
  for (std::size_t p = 0; p < s.triangles.size(); ++p) EXPECT_EQ(leaf[p], first[p]) << p;
}

}  // namespace
}  // namespace hrpp
