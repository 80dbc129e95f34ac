// Node layouts (host/bvh/gpu_layout.h, --bvh-layout): on every reference scene, the
// dfs-large-first layout is a well-formed tree (parent and depth links, every node and leaf
// placed once, the larger child right after its parent), differs from dfs only in numbering
// (the CPU reference answers and counts the same, bit for bit, on random rays), and the GPU
// kernels on it equal the CPU reference on it bit for bit.
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "gpu/gpu_tracer.h"
#include "vk/vulkan_context.h"
#include "gpu_test_context.h"
#include "test_scenes.h"
#include "trace/cpu_traversal.h"

namespace hrpp {
namespace {

using test::context;

float area(const glm::vec4& xy, float zlo, float zhi) {
  Aabb b;
  b.grow(glm::vec3(xy.x, xy.z, zlo));
  b.grow(glm::vec3(xy.y, xy.w, zhi));
  return b.area();
}

// Parent and depth links agree with the child links; every node and leaf is referenced once.
void expect_well_formed(const GpuBvh& g) {
  std::vector<int> node_refs(g.nodes.size(), 0), leaf_refs(g.leaves.size(), 0);
  node_refs[0] = 1;
  for (std::size_t i = 0; i < g.nodes.size(); ++i) {
    const gpu::BvhNode& n = g.nodes[i];
    for (int ref : {n.link.x, n.link.y}) {
      if (is_leaf_ref(ref)) {
        const gpu::BvhLeaf& l = g.leaves.at(leaf_index(ref));
        ++leaf_refs[leaf_index(ref)];
        EXPECT_EQ(l.parent, static_cast<int>(i));
        EXPECT_EQ(l.depth, static_cast<gpu::uint>(n.link.w + 1));
      } else {
        ASSERT_LT(static_cast<std::size_t>(ref), g.nodes.size());
        ++node_refs[ref];
        EXPECT_EQ(g.nodes[ref].link.z, static_cast<int>(i));
        EXPECT_EQ(g.nodes[ref].link.w, n.link.w + 1);
      }
    }
  }
  for (int c : node_refs) ASSERT_EQ(c, 1);
  for (int c : leaf_refs) ASSERT_EQ(c, 1);
}

std::vector<gpu::Ray> random_rays(const Aabb& box, std::size_t n) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> t(-0.2f, 1.2f), dir(-1.0f, 1.0f);
  std::vector<gpu::Ray> rays(n);
  for (gpu::Ray& r : rays)
    r = {box.lo + glm::vec3(t(rng), t(rng), t(rng)) * box.extent(), 0.0f,
         {dir(rng), dir(rng), dir(rng)}, 1e30f};
  return rays;
}

class NodeLayoutTest : public testing::TestWithParam<std::string> {};

TEST_P(NodeLayoutTest, LargeFirstRenumbersOnly) {
  const Scene scene = test::load_test_scene(GetParam());
  const Bvh bvh = build_bvh(scene, BvhConfig{});
  const GpuBvh dfs = make_gpu_layout(bvh, scene, NodeLayout::kDfs);
  const GpuBvh large = make_gpu_layout(bvh, scene, NodeLayout::kDfsLargeFirst);
  ASSERT_EQ(large.nodes.size(), dfs.nodes.size());
  ASSERT_EQ(large.leaves.size(), dfs.leaves.size());
  ASSERT_EQ(large.triangles.size(), dfs.triangles.size());
  expect_well_formed(dfs);
  expect_well_formed(large);
  // The larger child (ties: the left) follows its parent when it is interior.
  for (std::size_t i = 0; i < large.nodes.size(); ++i) {
    const gpu::BvhNode& n = large.nodes[i];
    const bool right = area(n.right_xy, n.lr_z.z, n.lr_z.w) > area(n.left_xy, n.lr_z.x, n.lr_z.y);
    const int first = right ? n.link.y : n.link.x;
    if (!is_leaf_ref(first)) {
      EXPECT_EQ(first, static_cast<int>(i) + 1) << "node " << i;
    }
  }
  // Same answers and the same work, ray by ray.
  for (const gpu::Ray& r : random_rays(bvh.nodes[0].bounds, 3000)) {
    TraversalCounters a, b;
    const gpu::Hit ha = trace_closest(dfs, r, &a), hb = trace_closest(large, r, &b);
    ASSERT_EQ(std::memcmp(&ha, &hb, sizeof ha), 0);
    const gpu::Hit aa = trace_any_hit(dfs, r, &a), ab = trace_any_hit(large, r, &b);
    ASSERT_EQ(std::memcmp(&aa, &ab, sizeof aa), 0);
    ASSERT_EQ(a.interior_visited, b.interior_visited);
    ASSERT_EQ(a.leaves_visited, b.leaves_visited);
    ASSERT_EQ(a.triangles_tested, b.triangles_tested);
  }
}

TEST_P(NodeLayoutTest, GpuEqualsCpuOnLargeFirst) {
  const Scene scene = test::load_test_scene(GetParam());
  const GpuBvh large =
      make_gpu_layout(build_bvh(scene, BvhConfig{}), scene, NodeLayout::kDfsLargeFirst);
  const std::vector<gpu::Ray> rays = random_rays(large.bounds, 4000);
  GpuTracer tracer(context(), large);
  const GpuTraceResult closest = tracer.trace(rays, QueryKind::kClosest);
  const GpuTraceResult any = tracer.trace(rays, QueryKind::kAny);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const gpu::Hit h = trace_closest(large, rays[i]);
    ASSERT_EQ(std::memcmp(&h, &closest.hits[i], sizeof h), 0) << "ray " << i;
    ASSERT_EQ(closest.hits[i].prim >= 0 ? 0 : -1, any.hits[i].prim) << "ray " << i;
  }
  EXPECT_EQ(closest.counters.rays, rays.size());
  EXPECT_EQ(context().validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Scenes, NodeLayoutTest, testing::ValuesIn(test::reference_scene_names()),
                         test::scene_param_name);

TEST(NodeLayout, NamesRoundTrip) {
  for (const auto& [layout, name] : kNodeLayoutNames) {
    EXPECT_STREQ(node_layout_name(layout), name);
    EXPECT_EQ(value_map(kNodeLayoutNames).at(name), layout);
  }
  EXPECT_EQ(value_map(kNodeLayoutNames).size(), kNodeLayoutNames.size());  // names differ
}

}  // namespace
}  // namespace hrpp
