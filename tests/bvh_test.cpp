// host/bvh/: binned SAH builder invariants on real meshes, the committed stand-in scenes and
// synthetic edge cases; the same tree for any thread count; the builder's parts (small-node SAH
// against binning, the chunked partition, the task pool); statistics and the 64-byte GPU layout.
#include <algorithm>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/bvh_stats.h"
#include "bvh/gpu_layout.h"
#include "bvh/ref_partition.h"
#include "bvh/sah_bins.h"
#include "bvh/small_node.h"
#include "common/task_pool.h"
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

// The same tree bit for bit: node boxes, children and leaf ranges, triangle order.
void expect_same_tree(const Bvh& a, const Bvh& b, const std::string& what) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size()) << what;
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    const Bvh::Node &x = a.nodes[i], &y = b.nodes[i];
    ASSERT_EQ(0, std::memcmp(&x.bounds, &y.bounds, sizeof(Aabb))) << what << ": node " << i;
    ASSERT_EQ(x.first, y.first) << what << ": node " << i;
    ASSERT_EQ(x.count, y.count) << what << ": node " << i;
  }
  EXPECT_EQ(a.prim_ids, b.prim_ids) << what;
  EXPECT_EQ(a.degenerate_count, b.degenerate_count) << what;
}

// Builds `scene` on 1, 2, 3 and 4 threads: every tree passes the layout invariants and all are
// the one-thread tree. Returns that tree.
Bvh expect_valid_on_any_thread_count(const Scene& scene, BvhConfig config = {}) {
  config.threads = 1;
  const Bvh one = build_bvh(scene, config);
  expect_valid_layout(scene, one, make_gpu_layout(one, scene), config.max_leaf_size);
  for (int threads : {2, 3, 4}) {
    config.threads = threads;
    const Bvh other = build_bvh(scene, config);
    expect_same_tree(one, other, std::to_string(threads) + " threads");
  }
  return one;
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

TEST(BvhEdgeCases, DegenerateTrianglesKeepTheirIdsButStayOut) {
  const Scene s = test::synthetic_scene({
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
  const Scene s = test::synthetic_scene({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
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
  const Scene s = test::synthetic_scene(tris);
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
  const Scene s = test::synthetic_scene(tris);
  const Bvh bvh = build_bvh(s);
  expect_valid_layout(s, bvh, make_gpu_layout(bvh, s), 4);
}

TEST(BvhEdgeCases, OneOrTwoTrianglesOnAnyThreadCount) {
  const Triangle a{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, b{{2, 0, 0}, {3, 0, 0}, {2, 1, 1}};
  for (const auto& tris : {std::vector<Triangle>{a}, std::vector<Triangle>{a, b},
                           std::vector<Triangle>{b, a}, std::vector<Triangle>{a, a}}) {
    const Scene s = test::synthetic_scene(tris);
    const Bvh bvh = expect_valid_on_any_thread_count(s);
    const GpuBvh g = make_gpu_layout(bvh, s);
    ASSERT_EQ(g.nodes.size(), 1u);  // one interior root over two leaves
    ASSERT_EQ(g.leaves.size(), 2u);
    EXPECT_EQ(g.leaves[0].triangle_count + g.leaves[1].triangle_count, tris.size());
  }
}

TEST(BvhEdgeCases, ManyEqualTrianglesOnAnyThreadCount) {
  // Large enough for the parallel top of the tree; no plane separates equal centroids, so every
  // split is an object median, down to leaves of max_leaf_size.
  const Scene s = test::synthetic_scene(std::vector<Triangle>(20000, Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  const Bvh bvh = expect_valid_on_any_thread_count(s);
  const BvhStats st = compute_bvh_stats(bvh);
  EXPECT_EQ(st.max_leaf_size, 4u);
  EXPECT_LE(st.max_depth, 14u);  // balanced: ceil(log2(20000 / 4)) + 1
}

TEST(BvhEdgeCases, DegenerateAndCollinearAmongValidOnAnyThreadCount) {
  std::vector<Triangle> tris;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (int i = 0; i < 6000; ++i) {
    const float f = static_cast<float>(i % 97), g = static_cast<float>(i / 97);
    switch (i % 5) {
      case 0: tris.push_back({{f, g, 0}, {f + 1, g, 0}, {f, g + 1, 0}}); break;          // valid
      case 1: tris.push_back({{f, g, 0}, {f + 1, g + 1, 1}, {f + 2, g + 2, 2}}); break;  // collinear
      case 2: tris.push_back({{f, g, 0}, {f, g, 0}, {f, g + 1, 0}}); break;              // a segment
      case 3: tris.push_back({{f, g, 0}, {f + 1, g, nan}, {f, g + 1, 0}}); break;        // NaN
      default: tris.push_back({{f, g, 1}, {f + 1, g, 1}, {inf, g + 1, 1}}); break;       // infinite
    }
  }
  const Scene s = test::synthetic_scene(tris);
  const Bvh bvh = expect_valid_on_any_thread_count(s);
  EXPECT_EQ(bvh.prim_ids.size(), 1200u);
  EXPECT_EQ(bvh.degenerate_count, 4800u);
}

TEST(BvhEdgeCases, OnlyDegenerateTrianglesGiveAnEmptyTree) {
  const Scene s = test::synthetic_scene({{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}}});
  const Bvh bvh = expect_valid_on_any_thread_count(s);
  EXPECT_TRUE(bvh.prim_ids.empty());
  EXPECT_EQ(bvh.degenerate_count, 2u);
  const GpuBvh g = make_gpu_layout(bvh, s);
  EXPECT_TRUE(g.triangles.empty());
}

// Random triangles in the unit cube, coordinates on a coarse grid so that many centroids and
// bin positions coincide (ties in the SAH sweep and the partition).
std::vector<Triangle> random_triangles(int n, unsigned seed, float grid) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f), size(0.0f, 0.05f);
  auto snap = [grid](float x) { return grid > 0 ? std::round(x * grid) / grid : x; };
  std::vector<Triangle> tris;
  for (int i = 0; i < n; ++i) {
    const glm::vec3 p{snap(u(rng)), snap(u(rng)), snap(u(rng))};
    tris.push_back({p, p + glm::vec3{size(rng), 0, size(rng)}, p + glm::vec3{0, size(rng), size(rng)}});
  }
  return tris;
}

TEST(BvhEdgeCases, RandomSoupsOnAnyThreadCount) {
  for (float grid : {0.0f, 64.0f, 4.0f}) {
    const Scene s = test::synthetic_scene(random_triangles(60000, 7, grid));
    BvhConfig c;
    expect_valid_on_any_thread_count(s, c);
    c.bin_count = 5;
    c.max_leaf_size = 1;
    expect_valid_on_any_thread_count(s, c);
  }
}

// The committed stand-in scenes (scenes/*.scene.json; the dragon is made by
// tools/fetch-scenes.sh) with the SAH cost of the trees of the sequential builder this one
// replaced (16 bins, leaves <= 4): the tree may not be worse. The two estimator scenes came
// later: their bound is this builder's cost when they were added.
struct StandIn {
  const char* name;
  double sah_before;
};
const StandIn kStandIns[] = {{"cornell", 12.596920},    {"teapot", 3.915268},
                             {"bunny", 5.043105},       {"bunny-complex", 5.553716},
                             {"lamborghini", 5.974062}, {"wall-lamp", 11.138054},
                             {"floor-panel", 3.923293}};

void PrintTo(const StandIn& s, std::ostream* os) { *os << s.name; }

TEST(StandInScenes, EveryCommittedManifestIsChecked) {
  std::set<std::string> listed{"dragon"};
  for (const StandIn& s : kStandIns) listed.insert(s.name);
  int manifests = 0;
  for (const auto& e : std::filesystem::directory_iterator(HRPP_TEST_SCENES_DIR)) {
    const std::string file = e.path().filename().string();
    const std::string suffix = ".scene.json";
    if (file.size() <= suffix.size() || file.compare(file.size() - suffix.size(), suffix.size(), suffix))
      continue;
    ++manifests;
    EXPECT_TRUE(listed.count(file.substr(0, file.size() - suffix.size()))) << file;
  }
  EXPECT_EQ(manifests, static_cast<int>(listed.size()));
}

class StandInSceneBvh : public testing::TestWithParam<StandIn> {};

TEST_P(StandInSceneBvh, ValidOnAnyThreadCountAndNoWorseSah) {
  const Scene scene = load_scene(GetParam().name);
  const BvhConfig config;
  const Bvh bvh = expect_valid_on_any_thread_count(scene, config);
  const BvhStats st = compute_bvh_stats(bvh, config);
  EXPECT_LE(st.sah_cost, GetParam().sah_before * (1.0 + 1e-6));
  EXPECT_LT(st.max_depth, static_cast<std::uint32_t>(HRPP_STACK_SIZE));
}

INSTANTIATE_TEST_SUITE_P(Scenes, StandInSceneBvh, testing::ValuesIn(kStandIns),
                         [](const testing::TestParamInfo<StandIn>& param) {
                           std::string n = param.param.name;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

// The builder's parts. References of random triangles (see random_triangles).
std::vector<bvh_build::PrimRef> random_refs(int n, unsigned seed, float grid) {
  std::vector<bvh_build::PrimRef> refs;
  std::uint32_t id = 0;
  for (const Triangle& t : random_triangles(n, seed, grid)) {
    bvh_build::PrimRef r{};
    const glm::vec3 lo = glm::min(glm::min(t.v0, t.v1), t.v2), hi = glm::max(glm::max(t.v0, t.v1), t.v2);
    r.set(simd::set3(lo.x, lo.y, lo.z), simd::set3(hi.x, hi.y, hi.z), id++);
    refs.push_back(r);
  }
  return refs;
}

bvh_build::Box4 centroid_bounds(const std::vector<bvh_build::PrimRef>& refs) {
  bvh_build::Box4 b;
  for (const bvh_build::PrimRef& r : refs) b.grow(r.centroid());
  return b;
}

bool same_box(const bvh_build::Box4& a, const bvh_build::Box4& b) {
  const Aabb x = a.aabb(), y = b.aabb();
  return std::memcmp(&x, &y, sizeof(Aabb)) == 0;
}

// Small nodes skip the bins: their split must be the one binning finds (axis, cost, children's
// boxes, and which references go left), with the children's centroid bounds.
TEST(BvhBuilderParts, SmallNodeSplitIsTheBinnedSplit) {
  const BvhConfig config;
  int splits = 0;
  for (unsigned trial = 0; trial < 3000; ++trial) {
    const int n = 2 + static_cast<int>(trial % (bvh_build::kMaxSmallNode - 1));
    std::vector<bvh_build::PrimRef> refs = random_refs(n, trial, trial % 3 == 0 ? 4.0f : 0.0f);
    const bvh_build::Box4 centroids = centroid_bounds(refs);
    bvh_build::Box4 bounds;
    for (const auto& r : refs) bounds.grow(bvh_build::Box4{r.lo4(), r.hi4()});
    const bvh_build::BinMap map(centroids, config.bin_count);
    bvh_build::SahBins bins;
    bins.clear(config.bin_count);
    bins.add(refs.data(), static_cast<std::uint32_t>(n), map);
    const bvh_build::Split binned = bvh_build::best_split(bins, map, centroids, bounds.area(), config);

    std::vector<bvh_build::PrimRef> moved = refs;
    bvh_build::SmallNode small;
    bvh_build::Split fast;
    std::uint32_t left_count = 1;
    if (n == 2) {
      fast = bvh_build::split_pair(moved.data(), centroids, bounds.area(), config);
    } else {
      small.load(refs.data(), static_cast<std::uint32_t>(n), map);
      fast = small.best_split(centroids, bounds.area(), config);
      if (fast.axis >= 0) left_count = small.partition(moved.data(), fast);
    }
    ASSERT_EQ(fast.axis, binned.axis) << "trial " << trial;
    if (binned.axis < 0) continue;
    ++splits;
    ASSERT_EQ(fast.cost, binned.cost) << "trial " << trial;
    EXPECT_TRUE(same_box(fast.left, binned.left) && same_box(fast.right, binned.right)) << trial;
    std::set<std::uint32_t> left_binned, left_fast;
    bvh_build::Box4 left_centroids, right_centroids;
    for (const auto& r : refs) {
      alignas(16) std::int32_t b[4];
      map.map(r.centroid(), b);
      const bool left = b[binned.axis] <= binned.bin;
      if (left) left_binned.insert(r.id());
      (left ? left_centroids : right_centroids).grow(r.centroid());
    }
    ASSERT_TRUE(fast.has_centroids);
    EXPECT_TRUE(same_box(fast.left_centroids, left_centroids) &&
                same_box(fast.right_centroids, right_centroids)) << trial;
    for (std::uint32_t i = 0; i < left_count; ++i) left_fast.insert(moved[i].id());
    EXPECT_EQ(left_fast, left_binned) << "trial " << trial;
  }
  EXPECT_GT(splits, 2500);
}

// The chunked partition gives the same order whether its chunks run on no pool or on 2 or 3
// threads, and it is a partition by the plane.
TEST(BvhBuilderParts, ChunkedPartitionIsTheSameOnAnyPool) {
  const std::vector<bvh_build::PrimRef> refs = random_refs(100000, 3, 64.0f);
  const bvh_build::BinMap map(centroid_bounds(refs), 16);
  for (int axis = 0; axis < 3; ++axis) {
    const bvh_build::Plane plane{&map, axis, 4 + 3 * axis};
    std::vector<bvh_build::PrimRef> first = refs;
    bvh_build::RefPartitioner part;
    const std::uint32_t mid = part.run(first.data(), 100, 99000, plane);
    for (std::uint32_t i = 100; i < 99000; ++i) {
      alignas(16) std::int32_t b[4];
      map.map(first[i].centroid(), b);
      ASSERT_EQ(b[axis] <= plane.bin, i < mid) << "reference " << i;
    }
    EXPECT_EQ(0, std::memcmp(first.data(), refs.data(), 100 * sizeof(refs[0])));  // outside kept
    for (int threads : {2, 3}) {
      TaskPool pool(threads);
      std::vector<bvh_build::PrimRef> other = refs;
      EXPECT_EQ(part.run(other.data(), 100, 99000, plane, &pool), mid);
      EXPECT_EQ(0, std::memcmp(first.data(), other.data(), refs.size() * sizeof(refs[0])));
    }
    std::multiset<std::uint32_t> a, b;
    for (std::size_t i = 0; i < refs.size(); ++i) a.insert(refs[i].id()), b.insert(first[i].id());
    EXPECT_EQ(a, b);
  }
}

TEST(BvhBuilderParts, TaskPoolRunsEveryTaskOnceAndRethrows) {
  TaskPool pool(3);
  ASSERT_EQ(pool.size(), 3);
  for (int round = 0; round < 50; ++round) {
    std::vector<std::atomic<int>> runs(1000);
    std::atomic<bool> bad_thread{false};
    pool.parallel_for(runs.size(), [&](std::size_t i, int thread) {
      runs[i].fetch_add(1);
      if (thread < 0 || thread >= 3) bad_thread = true;
    });
    for (const auto& r : runs) ASSERT_EQ(r.load(), 1);
    EXPECT_FALSE(bad_thread.load());
  }
  EXPECT_THROW(pool.parallel_for(100,
                                 [](std::size_t i, int) {
                                   if (i == 57) throw std::runtime_error("task 57");
                                 }),
               std::runtime_error);
  std::atomic<int> after{0};
  pool.parallel_for(10, [&](std::size_t, int) { after.fetch_add(1); });
  EXPECT_EQ(after.load(), 10);
}

// An exception thrown by a task on a worker thread (not the caller's) reaches parallel_for's
// caller, and the pool still works. The caller's task waits until a worker has run the other
// task, so a worker always throws, whatever the scheduler does.
TEST(BvhBuilderParts, TaskPoolRethrowsAWorkersException) {
  TaskPool pool(2);
  for (int round = 0; round < 20; ++round) {
    std::atomic<bool> worker_threw{false};
    std::string caught;
    try {
      pool.parallel_for(2, [&](std::size_t, int thread) {
        if (thread != 0) {
          worker_threw = true;
          throw std::runtime_error("thrown on thread " + std::to_string(thread));
        }
        while (!worker_threw.load()) std::this_thread::yield();
      });
    } catch (const std::runtime_error& e) {
      caught = e.what();
    }
    EXPECT_EQ(caught, "thrown on thread 1");  // the worker's, not the caller's
  }
  std::atomic<int> after{0};
  pool.parallel_for(4, [&](std::size_t, int) { after.fetch_add(1); });
  EXPECT_EQ(after.load(), 4);
}

// Once a task has thrown, the tasks not yet started are skipped. With the caller alone the tasks
// run in order, so exactly the ones up to the thrower ran.
TEST(BvhBuilderParts, TaskPoolSkipsTheTasksAfterAnException) {
  TaskPool pool(1);
  std::atomic<int> ran{0};
  EXPECT_THROW(pool.parallel_for(100,
                                 [&](std::size_t task, int) {
                                   ran.fetch_add(1);
                                   if (task == 3) throw std::runtime_error("task 3");
                                 }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 4);
}

}  // namespace
}  // namespace hrpp
