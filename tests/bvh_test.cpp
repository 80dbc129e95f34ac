// host/bvh/: binned SAH builder invariants on real meshes and synthetic edge cases, statistics,
// and the 64-byte GPU layout.
#include <algorithm>
#include <cstring>
#include <map>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/bvh_stats.h"
#include "bvh/gpu_layout.h"
#include "common/error.h"
#include "test_scenes.h"

namespace hrpp {
namespace {

Aabb left_box(const gpu::BvhNode& n) {
  return {{n.left_xy.x, n.left_xy.z, n.lr_z.x}, {n.left_xy.y, n.left_xy.w, n.lr_z.y}};
}
Aabb right_box(const gpu::BvhNode& n) {
  return {{n.right_xy.x, n.right_xy.z, n.lr_z.z}, {n.right_xy.y, n.right_xy.w, n.lr_z.w}};
}

// Checks every structural invariant of a GPU layout built from `scene`.
void expect_valid_layout(const Scene& scene, const Bvh& bvh, const GpuBvh& g, int max_leaf) {
  // Every non-degenerate triangle in exactly one leaf; degenerate ones in none.
  std::vector<int> seen(scene.triangles.size(), 0);
  for (const gpu::TriangleRecord& r : g.triangles) {
    ASSERT_LT(r.prim, scene.triangles.size());
    ++seen[r.prim];
  }
  std::uint32_t degenerate = 0;
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const bool deg = is_degenerate(scene.triangles[i]);
    degenerate += deg;
    ASSERT_EQ(seen[i], deg ? 0 : 1) << "triangle " << i;
  }
  EXPECT_EQ(bvh.degenerate_count, degenerate);

  // Walk from the root: child boxes inside parent boxes, leaf boxes around their triangles,
  // parent links and depths consistent, every node and leaf reached exactly once.
  std::vector<int> node_seen(g.nodes.size(), 0), leaf_seen(g.leaves.size(), 0);
  struct Item { int ref; Aabb box; int parent; int depth; };
  std::vector<Item> stack{{0, g.bounds, -1, 0}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    if (is_leaf_ref(it.ref)) {
      const gpu::BvhLeaf& leaf = g.leaves[leaf_index(it.ref)];
      ++leaf_seen[leaf_index(it.ref)];
      EXPECT_EQ(leaf.parent, it.parent);
      EXPECT_EQ(static_cast<int>(leaf.depth), it.depth);
      EXPECT_LE(static_cast<int>(leaf.triangle_count), max_leaf);
      for (gpu::uint i = leaf.first_triangle; i < leaf.first_triangle + leaf.triangle_count; ++i) {
        const gpu::TriangleRecord& r = g.triangles[i];
        for (const glm::vec3& v : {r.v0, r.v1, r.v2}) {
          Aabb p;
          p.grow(v);
          ASSERT_TRUE(it.box.contains(p)) << "leaf box misses a vertex of triangle " << r.prim;
        }
      }
      continue;
    }
    ASSERT_GE(it.ref, 0);
    ASSERT_LT(it.ref, static_cast<int>(g.nodes.size()));
    ++node_seen[it.ref];
    const gpu::BvhNode& n = g.nodes[it.ref];
    EXPECT_EQ(n.link.z, it.parent);
    EXPECT_EQ(n.link.w, it.depth);
    const Aabb l = left_box(n), r = right_box(n);
    if (!l.empty()) {
      EXPECT_TRUE(it.box.contains(l)) << "node " << it.ref;
    }
    if (!r.empty()) {
      EXPECT_TRUE(it.box.contains(r)) << "node " << it.ref;
    }
    stack.push_back({n.link.x, l, it.ref, it.depth + 1});
    stack.push_back({n.link.y, r, it.ref, it.depth + 1});
  }
  for (int s : node_seen) EXPECT_EQ(s, 1);
  for (int s : leaf_seen) EXPECT_EQ(s, 1);
}

class RealMeshBvh : public testing::TestWithParam<std::string> {};

TEST_P(RealMeshBvh, InvariantsHoldAndStatsAreReported) {
  const Scene scene = test::load_test_scene(GetParam());
  BvhConfig config;
  const Bvh bvh = build_bvh(scene, config);
  const GpuBvh g = make_gpu_layout(bvh, scene);
  expect_valid_layout(scene, bvh, g, config.max_leaf_size);

  const BvhStats s = compute_bvh_stats(bvh, config);
  EXPECT_EQ(s.triangles + s.degenerate, scene.triangles.size());
  EXPECT_EQ(s.leaves, g.leaves.size());
  EXPECT_EQ(s.interior_nodes, g.nodes.size());
  EXPECT_EQ(s.leaves, s.interior_nodes + 1);  // binary tree
  EXPECT_GT(s.sah_cost, 1.0);                 // at least one node visit and one triangle test
  EXPECT_TRUE(std::isfinite(s.sah_cost));
  EXPECT_LE(s.max_leaf_size, static_cast<std::uint32_t>(config.max_leaf_size));
  EXPECT_GE(s.mean_leaf_size, 1.0);
  EXPECT_LT(s.max_depth, static_cast<std::uint32_t>(HRPP_STACK_SIZE));
}

TEST_P(RealMeshBvh, LayoutIsTheSameWithOneOrTwoThreads) {
  const Scene scene = test::load_test_scene(GetParam());
  BvhConfig one, two;
  one.threads = 1;
  two.threads = 2;
  const GpuBvh a = make_gpu_layout(build_bvh(scene, one), scene);
  const GpuBvh b = make_gpu_layout(build_bvh(scene, two), scene);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  EXPECT_EQ(0, std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(a.nodes[0])));
  EXPECT_EQ(0, std::memcmp(a.triangles.data(), b.triangles.data(),
                           a.triangles.size() * sizeof(a.triangles[0])));
}

INSTANTIATE_TEST_SUITE_P(Scenes, RealMeshBvh, testing::ValuesIn(test::reference_scene_names()),
                         test::scene_param_name);

TEST(BvhConfigTest, BinCountsAndLeafSizesAllGiveValidTrees) {
  const Scene scene = test::load_test_scene("meshes/utah_teapot.glb");
  double cost_2bins = 0.0, cost_32bins = 0.0;
  for (int bins : {2, 8, 32, 64})
    for (int leaf : {1, 4, 16}) {
      BvhConfig c;
      c.bin_count = bins;
      c.max_leaf_size = leaf;
      const Bvh bvh = build_bvh(scene, c);
      expect_valid_layout(scene, bvh, make_gpu_layout(bvh, scene), leaf);
      if (leaf == 4 && bins == 2) cost_2bins = compute_bvh_stats(bvh, c).sah_cost;
      if (leaf == 4 && bins == 32) cost_32bins = compute_bvh_stats(bvh, c).sah_cost;
    }
  EXPECT_LT(cost_32bins, cost_2bins);  // more candidate planes find a cheaper tree
}

TEST(BvhConfigTest, OutOfRangeSettingsAreErrors) {
  const Scene scene = builtin_cornell();
  BvhConfig c;
  c.bin_count = 1;
  EXPECT_THROW(build_bvh(scene, c), Error);
  c = {};
  c.max_leaf_size = 0;
  EXPECT_THROW(build_bvh(scene, c), Error);
}

Scene synthetic(std::vector<Triangle> tris) {
  Scene s;
  s.name = "synthetic";
  s.triangles = std::move(tris);
  s.shading.resize(s.triangles.size());
  s.materials.resize(1);
  return s;
}

TEST(BvhEdgeCases, DegenerateTrianglesKeepTheirIdsButStayOut) {
  const Scene s = synthetic({
      {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
      {{0, 0, 0}, {0, 0, 0}, {0, 1, 0}},  // repeated vertex
      {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}},  // collinear
      {{5, 0, 0}, {6, 0, 0}, {5, 1, 0}},
      {{3, 3, 3}, {3, 3, 3}, {3, 3, 3}},  // a point
  });
  const Bvh bvh = build_bvh(s);
  EXPECT_EQ(bvh.degenerate_count, 3u);
  const GpuBvh g = make_gpu_layout(bvh, s);
  expect_valid_layout(s, bvh, g, 4);
  std::vector<gpu::uint> ids;
  for (const auto& r : g.triangles) ids.push_back(r.prim);
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(ids, (std::vector<gpu::uint>{0, 3}));
}

TEST(BvhEdgeCases, OneTriangleGetsAnInteriorRootAndAnEmptyLeaf) {
  const Scene s = synthetic({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
  const Bvh bvh = build_bvh(s);
  const GpuBvh g = make_gpu_layout(bvh, s);
  ASSERT_EQ(g.nodes.size(), 1u);
  ASSERT_EQ(g.leaves.size(), 2u);
  EXPECT_EQ(g.leaves[0].triangle_count, 1u);
  EXPECT_EQ(g.leaves[1].triangle_count, 0u);
  expect_valid_layout(s, bvh, g, 4);
}

TEST(BvhEdgeCases, IdenticalTrianglesAreSplitByMedianNotOneHugeLeaf) {
  std::vector<Triangle> tris(100, Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const Scene s = synthetic(tris);
  BvhConfig c;
  c.max_leaf_size = 4;
  const Bvh bvh = build_bvh(s, c);
  expect_valid_layout(s, bvh, make_gpu_layout(bvh, s), 4);
}

TEST(BvhEdgeCases, HugeAndTinyCoordinates) {
  std::vector<Triangle> tris;
  for (int i = 0; i < 50; ++i) {
    const float f = static_cast<float>(i);
    tris.push_back({{1e6f + f, 1e6f, 1e6f}, {1e6f + f + 0.5f, 1e6f, 1e6f}, {1e6f + f, 1e6f + 1, 1e6f}});
    tris.push_back({{f * 1e-6f, 0, 0}, {f * 1e-6f + 1e-7f, 0, 0}, {f * 1e-6f, 1e-7f, 0}});
  }
  const Scene s = synthetic(tris);
  const Bvh bvh = build_bvh(s);
  expect_valid_layout(s, bvh, make_gpu_layout(bvh, s), 4);
}

}  // namespace
}  // namespace hrpp
