// host/reference/embree_tracer: Embree agrees with the CPU reference (trace/cpu_traversal.h)
// on >= 10k rays of each batch kind (primary, AO, diffuse) for the Cornell box, the teapot and
// the bunny: same triangle and t within 1e-5 relative. Embree's triangle test is not watertight,
// so a different triangle at the same t (tie) is accepted and fewer than 0.1% of the rays may
// disagree (edges, vertices); those are printed. Skipped when the build has no Embree.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "common/error.h"
#include "reference/embree_tracer.h"
#include "test_scenes.h"
#include "trace/cpu_traversal.h"
#include "trace/ray_batches.h"

namespace hrpp {
namespace {

constexpr std::uint32_t kSide = 112;  // 12,544 primaries
constexpr std::size_t kSecondary = 12000;

class EmbreeVsReference : public testing::TestWithParam<std::string> {};

struct Tally {
  std::size_t rays = 0, ties = 0, disagreements = 0;
};

// Compares closest hits or occlusion (`kind`) of Embree and the CPU reference.
Tally compare(const GpuBvh& bvh, const EmbreeTracer& embree, std::span<const gpu::Ray> rays,
              QueryKind kind, const char* what, float diagonal) {
  Tally tally;
  const bool any_hit = kind == QueryKind::kAny;
  const std::vector<gpu::Hit> ref = trace_batch_cpu(bvh, rays, kind);
  const std::vector<gpu::Hit> got = embree.trace(rays, kind);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ++tally.rays;
    const gpu::Hit& r = ref[i];
    const gpu::Hit& e = got[i];
    bool ok;
    if (any_hit || r.prim < 0 || e.prim < 0) {
      ok = (r.prim >= 0) == (e.prim >= 0) && (any_hit || r.prim == e.prim);
    } else {
      ok = std::fabs(e.t - r.t) <= 1e-5f * std::fabs(r.t) + 1e-7f * diagonal;
      if (ok && r.prim != e.prim) ++tally.ties;
      // The barycentrics agree too when the triangle does (loosely: Embree computes them its way).
      if (ok && r.prim == e.prim) {
        EXPECT_NEAR(e.u, r.u, 1e-3f) << what << " ray " << i;
        EXPECT_NEAR(e.v, r.v, 1e-3f) << what << " ray " << i;
      }
    }
    if (!ok) {
      ++tally.disagreements;
      const gpu::Ray& ray = rays[i];
      std::printf("  %s ray %zu o=(%.9g %.9g %.9g) d=(%.9g %.9g %.9g) tmax %g: reference prim %d t "
                  "%.9g, Embree prim %d t %.9g\n",
                  what, i, ray.origin.x, ray.origin.y, ray.origin.z, ray.dir.x, ray.dir.y,
                  ray.dir.z, ray.tmax, r.prim, r.t, e.prim, e.t);
    }
  }
  std::printf("%s: %zu rays, %zu ties, %zu disagreements\n", what, tally.rays, tally.ties,
              tally.disagreements);
  return tally;
}

TEST_P(EmbreeVsReference, SameHitsOnEveryBatchKind) {
  if (!embree_available()) GTEST_SKIP() << "Embree not available in this build";
  const Scene scene = test::load_test_scene(GetParam());
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  const EmbreeTracer embree(scene);
  RayBatchConfig c;
  c.width = c.height = kSide;
  c.secondary_count = kSecondary;
  c.seed = 11;
  c.jitter = true;
  const RayBatches b = make_ray_batches(scene, bvh, c);
  ASSERT_GE(b.primary.size(), 10000u);
  ASSERT_EQ(b.ao.rays.size(), kSecondary);

  struct Case {
    const char* what;
    std::span<const gpu::Ray> rays;
    QueryKind kind;
  };
  const Case cases[] = {{"primary closest", b.primary, QueryKind::kClosest},
                        {"ao any", b.ao.rays, QueryKind::kAny},
                        {"ao closest", b.ao.rays, QueryKind::kClosest},
                        {"diffuse closest", b.diffuse.rays, QueryKind::kClosest},
                        {"diffuse any", b.diffuse.rays, QueryKind::kAny}};
  for (const Case& k : cases) {
    const Tally t = compare(bvh, embree, k.rays, k.kind, k.what, b.scene_diagonal);
    EXPECT_LT(static_cast<double>(t.disagreements), 0.001 * static_cast<double>(t.rays))
        << k.what << ": " << t.disagreements << " of " << t.rays << " rays disagree";
  }
}

TEST_P(EmbreeVsReference, SingleRayQueriesMatchTheBatch) {
  if (!embree_available()) GTEST_SKIP() << "Embree not available in this build";
  const Scene scene = test::load_test_scene(GetParam());
  const EmbreeTracer embree(scene);
  const std::vector<gpu::Ray> rays = make_primary_rays(scene.cameras[0], 32, 32, false, 1);
  const std::vector<gpu::Hit> closest = embree.trace(rays, QueryKind::kClosest, 2);
  const std::vector<gpu::Hit> any = embree.trace(rays, QueryKind::kAny, 2);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const gpu::Hit h = embree.closest(rays[i]);
    ASSERT_EQ(h.prim, closest[i].prim);
    ASSERT_EQ(h.t, closest[i].t);
    ASSERT_EQ(embree.occluded(rays[i]), any[i].prim == 0);
    ASSERT_EQ(any[i].prim >= 0, closest[i].prim >= 0);
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, EmbreeVsReference,
                         testing::Values("builtin:cornell", "meshes/utah_teapot.glb",
                                         "meshes/mcguire_bunny.glb"),
                         test::scene_param_name);

TEST(Embree, AvailabilityIsReported) {
  EXPECT_FALSE(embree_version().empty());
  if (!embree_available()) {
    EXPECT_THROW(EmbreeTracer(load_scene("builtin:cornell")), Error);
  }
}

}  // namespace
}  // namespace hrpp
