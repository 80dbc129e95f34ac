// host/trace/: the CPU reference traversal on the GPU layout equals brute force over every
// triangle (same id, same t; ties aside) on >= 10k rays per scene, closest and any hit.
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "test_scenes.h"
#include "trace/brute_force.h"
#include "trace/cpu_traversal.h"

namespace hrpp {
namespace {

constexpr int kRaysPerScene = 10000;

// Random rays over a scene: 40% from a random point in the (enlarged) bounds towards a random
// point on a random triangle, 40% in a uniformly random direction, 20% axis-parallel (one or two
// zero direction components). A quarter get a finite random tmax.
std::vector<gpu::Ray> random_rays(const Scene& scene, const Aabb& bounds, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const glm::vec3 pad = 0.25f * bounds.extent();
  const glm::vec3 lo = bounds.lo - pad, ext = bounds.extent() + 2.0f * pad;
  const float diag = glm::length(ext);
  std::vector<gpu::Ray> rays(kRaysPerScene);
  for (int i = 0; i < kRaysPerScene; ++i) {
    gpu::Ray& r = rays[i];
    r.origin = lo + glm::vec3(u01(rng), u01(rng), u01(rng)) * ext;
    r.tmin = 0.0f;
    r.tmax = std::numeric_limits<float>::infinity();
    const int kind = i % 5;
    if (kind < 2) {
      const Triangle& t = scene.triangles[rng() % scene.triangles.size()];
      float a = u01(rng), b = u01(rng);
      if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
      r.dir = t.v0 + a * (t.v1 - t.v0) + b * (t.v2 - t.v0) - r.origin;
    } else if (kind < 4) {
      const float z = 2.0f * u01(rng) - 1.0f, phi = 6.2831853f * u01(rng);
      const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
      r.dir = {s * std::cos(phi), s * std::sin(phi), z};
    } else {
      r.dir = glm::vec3(0.0f);
      const int axis = static_cast<int>(rng() % 3);
      r.dir[axis] = u01(rng) < 0.5f ? -1.0f : 1.0f;
      if (rng() % 2) r.dir[(axis + 1) % 3] = u01(rng) - 0.5f;  // two zero components otherwise one
    }
    if (glm::length(r.dir) == 0.0f) r.dir = {0, 0, 1};
    if (i % 4 == 3) r.tmax = u01(rng) * diag;
  }
  return rays;
}

struct Mismatch {
  int ray;
  gpu::Hit bvh, brute;
};

class ReferenceTraversal : public testing::TestWithParam<std::string> {};

TEST_P(ReferenceTraversal, EqualsBruteForceOnRandomRays) {
  const Scene scene = test::load_test_scene(GetParam());
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  const std::vector<gpu::Ray> rays = random_rays(scene, bvh.bounds, 1234);

  std::vector<gpu::Hit> closest(rays.size()), brute(rays.size());
  std::vector<char> any(rays.size()), brute_any(rays.size());
  std::vector<TraversalCounters> counters(2);
  // Brute force is the slow part: split the rays over two threads.
  auto work = [&](int part) {
    for (std::size_t i = part; i < rays.size(); i += 2) {
      closest[i] = trace_closest(bvh, rays[i], &counters[part]);
      any[i] = trace_any(bvh, rays[i]);
      brute[i] = brute_force_closest(scene, rays[i]);
      brute_any[i] = brute_force_any(scene, rays[i]);
    }
  };
  std::thread second(work, 1);
  work(0);
  second.join();

  int hits = 0, ties = 0;
  std::vector<Mismatch> mismatches;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const gpu::Hit& a = closest[i];
    const gpu::Hit& b = brute[i];
    hits += a.prim >= 0;
    EXPECT_EQ(static_cast<bool>(any[i]), static_cast<bool>(brute_any[i])) << "ray " << i;
    EXPECT_EQ(static_cast<bool>(any[i]), a.prim >= 0) << "ray " << i;
    if (a.prim == b.prim) {
      if (a.prim >= 0) {
        EXPECT_NEAR(a.t, b.t, 1e-6f * std::abs(b.t)) << "ray " << i;
        EXPECT_EQ(a.u, b.u);
        EXPECT_EQ(a.v, b.v);
      }
      continue;
    }
    if (a.prim >= 0 && b.prim >= 0 && a.t == b.t) {
      ++ties;  // both triangles at the same distance: either answer is right
      continue;
    }
    mismatches.push_back({static_cast<int>(i), a, b});
  }
  for (const Mismatch& m : mismatches)
    ADD_FAILURE() << "ray " << m.ray << ": bvh prim " << m.bvh.prim << " t " << m.bvh.t
                  << ", brute force prim " << m.brute.prim << " t " << m.brute.t;
  // The ray set is built to hit often; if it did not, the test would prove little.
  EXPECT_GT(hits, kRaysPerScene / 3);
  EXPECT_LT(ties, kRaysPerScene / 100);

  TraversalCounters c = counters[0];
  c += counters[1];
  EXPECT_EQ(c.rays, static_cast<std::uint64_t>(kRaysPerScene));
  EXPECT_EQ(c.hits, static_cast<std::uint64_t>(hits));
  EXPECT_GE(c.triangles_tested, c.hits);
  EXPECT_GE(c.interior_visited, c.rays);  // every valid ray tests the root's children
  // The point of a BVH: far fewer triangle tests than brute force.
  EXPECT_LT(c.triangles_tested, c.rays * scene.triangles.size() / 2 + c.rays * 8);
}

INSTANTIATE_TEST_SUITE_P(Scenes, ReferenceTraversal,
                         testing::ValuesIn(test::reference_scene_names()),
                         test::scene_param_name);

// A closed box of 12 triangles around the origin: rays from inside must always hit (no leaks
// through shared edges or vertices), including rays aimed exactly at edges and corners.
TEST(ReferenceTraversalEdges, RaysFromInsideAClosedBoxNeverEscape) {
  Scene s;
  const glm::vec3 p[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                          {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const int quads[6][4] = {{0, 1, 2, 3}, {4, 7, 6, 5}, {0, 4, 5, 1},
                           {3, 2, 6, 7}, {0, 3, 7, 4}, {1, 5, 6, 2}};
  for (const auto& q : quads) {
    s.triangles.push_back({p[q[0]], p[q[1]], p[q[2]]});
    s.triangles.push_back({p[q[0]], p[q[2]], p[q[3]]});
  }
  s.shading.resize(s.triangles.size());
  const GpuBvh bvh = make_gpu_layout(build_bvh(s), s);
  int escapes = 0, tested = 0;
  const glm::vec3 origins[] = {{0, 0, 0}, {0.25f, -0.5f, 0.125f}, {-1, 0, 0} /* on a face */};
  for (const glm::vec3& o : origins)
    for (int x = -2; x <= 2; ++x)
      for (int y = -2; y <= 2; ++y)
        for (int z = -2; z <= 2; ++z) {
          if (x == 0 && y == 0 && z == 0) continue;
          const gpu::Ray ray{o, 0.0f, glm::vec3(x, y, z) * 0.5f,
                             std::numeric_limits<float>::infinity()};
          ++tested;
          const gpu::Hit h = trace_closest(bvh, ray);
          const gpu::Hit b = brute_force_closest(s, ray);
          EXPECT_EQ(h.prim >= 0, b.prim >= 0);
          escapes += h.prim < 0;
        }
  EXPECT_EQ(tested, 3 * 124);
  // The origin on the face x = -1 sees rays with dx <= 0 leave at t = 0 through that face:
  // still a hit (t = 0 >= tmin = 0), so nothing escapes.
  EXPECT_EQ(escapes, 0);
}

TEST(ReferenceTraversalEdges, InvalidRaysMissAndNeverHang) {
  const Scene s = builtin_cornell();
  const GpuBvh bvh = make_gpu_layout(build_bvh(s), s);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const gpu::Ray bad[] = {
      {{nan, 270, 270}, 0, {0, 0, 1}, inf}, {{270, 270, 270}, 0, {nan, 0, 1}, inf},
      {{inf, 270, 270}, 0, {0, 0, 1}, inf}, {{270, 270, 270}, 0, {0, inf, 0}, inf},
      {{270, 270, 270}, 0, {0, 0, 0}, inf}, {{270, 270, 270}, nan, {0, 0, 1}, inf},
  };
  for (const gpu::Ray& r : bad) {
    EXPECT_EQ(trace_closest(bvh, r).prim, -1);
    EXPECT_FALSE(trace_any(bvh, r));
    EXPECT_EQ(brute_force_closest(s, r).prim, -1);
  }
}

TEST(ReferenceTraversalEdges, TiesGoToTheLowerTriangleId) {
  // Two coincident triangles with ids 0 and 1 (and a copy later): the lower id must win.
  Scene s;
  const Triangle t{{-1, -1, 5}, {1, -1, 5}, {0, 1, 5}};
  s.triangles = {{{10, 10, 10}, {11, 10, 10}, {10, 11, 10}}, t, t, t};
  s.shading.resize(s.triangles.size());
  const GpuBvh bvh = make_gpu_layout(build_bvh(s), s);
  const gpu::Ray r{{0, 0, 0}, 0, {0, 0, 1}, std::numeric_limits<float>::infinity()};
  EXPECT_EQ(trace_closest(bvh, r).prim, 1);
  EXPECT_EQ(brute_force_closest(s, r).prim, 1);
  EXPECT_EQ(trace_closest(bvh, r).t, 5.0f);
}

}  // namespace
}  // namespace hrpp
