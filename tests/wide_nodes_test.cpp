// The 4-wide node formats (host/bvh/wide_nodes.h): on every stand-in and on degenerate inputs
// (one triangle, equal triangles, a flat scene, subnormal, tiny, huge and translated
// coordinates) the wide nodes form a tree over the binary layout's leaves (each leaf that holds
// triangles and each node below the root referenced once, at most four children, fewer nodes
// than the binary layout; both formats the same tree), and every child box as the traversal
// tests it (WideNode: decoded by shaders/shared/wide_node.h) holds the exact box of the
// triangles under the child, also as a device that flushes subnormals computes it. A scene too
// wide for the 8-bit grid is a one-line error naming the option.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "common/error.h"
#include "test_scenes.h"
#include "wide_node.h"

namespace hrpp {
namespace {

float flushed(float x) { return std::fpclassify(x) == FP_SUBNORMAL ? std::copysign(0.0f, x) : x; }

// A wide node's children as the traversal tests them, whatever the format.
struct WideChildren {
  glm::ivec4 child;
  gpu::vec3 lo[HRPP_WIDE_CHILDREN], hi[HRPP_WIDE_CHILDREN];
};

WideChildren children_of(const GpuBvh& g, int node) {
  WideChildren c;
  if (g.format() == NodeFormat::kWide4) {
    const gpu::WideNode& n = g.wide_nodes.at(node);
    c.child = n.child;
    for (int i = 0; i < HRPP_WIDE_CHILDREN; ++i)
      gpu::hrpp_wide_child_box(n, gpu::hrpp_grid_steps(n), static_cast<gpu::uint>(i), c.lo[i],
                               c.hi[i]);
    return c;
  }
  const gpu::WideFloatNode& n = g.wide_float_nodes.at(node);
  c.child = n.child;
  for (int i = 0; i < HRPP_WIDE_CHILDREN; ++i) {
    c.lo[i] = {n.lo_x[i], n.lo_y[i], n.lo_z[i]};
    c.hi[i] = {n.hi_x[i], n.hi_y[i], n.hi_z[i]};
  }
  return c;
}

std::size_t wide_node_count(const GpuBvh& g) {
  return g.format() == NodeFormat::kWide4 ? g.wide_nodes.size() : g.wide_float_nodes.size();
}

class WideTreeChecker {
 public:
  explicit WideTreeChecker(const GpuBvh& g)
      : g_(g), node_refs_(wide_node_count(g), 0), leaf_refs_(g.leaves.size(), 0) {}

  void check() {
    ASSERT_NE(g_.format(), NodeFormat::kBinary);
    ASSERT_FALSE(node_refs_.empty());
    EXPECT_LE(node_refs_.size(), g_.nodes.size());
    node_refs_[0] = 1;
    subtree_box(0);
    for (int c : node_refs_) EXPECT_EQ(c, 1);
    for (std::size_t i = 0; i < g_.leaves.size(); ++i)
      if (g_.leaves[i].triangle_count > 0) {
        EXPECT_EQ(leaf_refs_[i], 1) << "leaf " << i;
      }
  }

 private:
  // The exact box of the triangles under child reference `ref`; checks its node's boxes.
  Aabb subtree_box(int ref) {
    Aabb box;
    if (is_leaf_ref(ref)) {
      const gpu::BvhLeaf& leaf = g_.leaves.at(leaf_index(ref));
      ++leaf_refs_.at(leaf_index(ref));
      for (gpu::uint i = leaf.first_triangle; i < leaf.first_triangle + leaf.triangle_count; ++i)
        for (const glm::vec3& v : {g_.triangles[i].v0, g_.triangles[i].v1, g_.triangles[i].v2})
          box.grow(v);
      return box;
    }
    const WideChildren n = children_of(g_, ref);
    for (int i = 0; i < HRPP_WIDE_CHILDREN; ++i) {
      const int child = n.child[i];
      if (child == HRPP_WIDE_EMPTY_SLOT) continue;
      if (!is_leaf_ref(child) && ++node_refs_.at(child) > 1) continue;  // counted: not a tree
      const Aabb exact = subtree_box(child);
      for (int a = 0; a < 3 && !exact.empty(); ++a) {
        // A decoded bound is a computed result, which a device may flush to zero; a float
        // node's bounds are stored values, as the binary layout's are.
        const bool decoded = g_.format() == NodeFormat::kWide4;
        const float lo = n.lo[i][a], hi = n.hi[i][a];
        const float lo_flushed = decoded ? flushed(lo) : lo, hi_flushed = decoded ? flushed(hi) : hi;
        EXPECT_TRUE(lo <= exact.lo[a] && lo_flushed <= exact.lo[a])
            << "node " << ref << " child " << i << " axis " << a << ": " << lo << " > "
            << exact.lo[a];
        EXPECT_TRUE(hi >= exact.hi[a] && hi_flushed >= exact.hi[a])
            << "node " << ref << " child " << i << " axis " << a << ": " << hi << " < "
            << exact.hi[a];
        EXPECT_TRUE(std::isfinite(lo) && std::isfinite(hi));
      }
      box.grow(exact);
    }
    return box;
  }

  const GpuBvh& g_;
  std::vector<int> node_refs_, leaf_refs_;
};

GpuBvh wide_layout(const Scene& scene, NodeFormat format = NodeFormat::kWide4) {
  return make_gpu_layout(build_bvh(scene, BvhConfig{}), scene, NodeLayout::kDfs, format);
}

constexpr NodeFormat kWideFormats[] = {NodeFormat::kWide4, NodeFormat::kWide4Float};

class WideNodes : public testing::TestWithParam<std::string> {};

TEST_P(WideNodes, FormATreeWhoseBoxesHoldTheirChildren) {
  const Scene scene = test::load_test_scene(GetParam());
  const GpuBvh q = wide_layout(scene), f = wide_layout(scene, NodeFormat::kWide4Float);
  for (const GpuBvh* g : {&q, &f}) {
    SCOPED_TRACE(node_format_name(g->format()));
    WideTreeChecker(*g).check();
    // Collapsing halves the levels: well under the binary node count.
    EXPECT_LT(wide_node_count(*g) * 2, g->nodes.size() + 2) << GetParam();
  }
  EXPECT_EQ(q.format(), NodeFormat::kWide4);
  EXPECT_EQ(f.format(), NodeFormat::kWide4Float);
  // Both formats are the same tree: the same child references.
  ASSERT_EQ(q.wide_nodes.size(), f.wide_float_nodes.size());
  for (std::size_t i = 0; i < q.wide_nodes.size(); ++i)
    ASSERT_EQ(q.wide_nodes[i].child, f.wide_float_nodes[i].child) << "node " << i;
}

INSTANTIATE_TEST_SUITE_P(StandIns, WideNodes, testing::ValuesIn(test::reference_scene_names()),
                         test::scene_param_name);

// A grid of `n` × `n` unit triangles at `scale`, moved by `offset`.
std::vector<Triangle> triangle_grid(int n, float scale, glm::vec3 offset) {
  std::vector<Triangle> tris;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const glm::vec3 p = offset + scale * glm::vec3(i, j, (i * 7 + j * 3) % 5);
      tris.push_back({p, p + glm::vec3(scale, 0, 0), p + glm::vec3(0, scale, scale)});
    }
  return tris;
}

TEST(WideNodes, DegenerateAndExtremeInputs) {
  const std::vector<std::pair<std::string, std::vector<Triangle>>> cases = {
      {"one triangle", {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}},
      {"equal triangles", std::vector<Triangle>(50, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}})},
      {"flat", [] {
         std::vector<Triangle> t = triangle_grid(12, 1.0f, glm::vec3(0));
         for (Triangle& x : t) x.v0.z = x.v1.z = x.v2.z = 2.0f;
         return t;
       }()},
      {"subnormal low corner below 0", triangle_grid(8, 1.0f, glm::vec3(-3e-40f))},
      {"subnormal low corner above 0", triangle_grid(8, 1.0f, glm::vec3(3e-40f))},
      {"tiny", triangle_grid(8, 1e-30f, glm::vec3(0))},
      {"huge", triangle_grid(8, 1e30f, glm::vec3(-4e30f))},
      {"translated", triangle_grid(8, 1e-3f, glm::vec3(1e6f, -1e6f, 1e6f))},
      {"near the largest float", triangle_grid(4, 3e37f, glm::vec3(-6e37f))},
  };
  for (const auto& [name, tris] : cases)
    for (const NodeFormat f : kWideFormats) {
      SCOPED_TRACE(name + ", " + node_format_name(f));
      WideTreeChecker(wide_layout(test::synthetic_scene(tris), f)).check();
    }
}

TEST(WideNodes, ASceneTooWideForTheGridNamesTheOption) {
  const Scene scene = test::synthetic_scene(
      {{{-3e38f, 0, 0}, {-3e38f, 1, 0}, {-3e38f, 0, 1}}, {{3e38f, 0, 0}, {3e38f, 1, 0}, {3e38f, 0, 1}}});
  try {
    wide_layout(scene);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--bvh-nodes wide4"), std::string::npos) << e.what();
  }
}

TEST(WideNodes, NamesRoundTrip) {
  for (const auto& [format, name] : kNodeFormatNames) {
    EXPECT_STREQ(node_format_name(format), name);
    EXPECT_EQ(value_map(kNodeFormatNames).at(name), format);
  }
  EXPECT_EQ(value_map(kNodeFormatNames).size(), kNodeFormatNames.size());  // names differ
}

}  // namespace
}  // namespace hrpp
