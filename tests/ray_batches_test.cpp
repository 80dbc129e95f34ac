// host/trace/ray_batches: Aila–Laine batches are deterministic for a seed, have the documented
// counts, origins and tmax, and secondary origins (Wächter–Binder offsets) do not re-hit the
// triangle they leave.
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "test_scenes.h"
#include "trace/cpu_traversal.h"
#include "trace/offset_ray.h"
#include "trace/ray_batches.h"

namespace hrpp {
namespace {

constexpr std::uint32_t kWidth = 96, kHeight = 64;
constexpr std::size_t kSecondary = 20000;

RayBatchConfig small_config(std::uint64_t seed = 7) {
  RayBatchConfig c;
  c.width = kWidth;
  c.height = kHeight;
  c.secondary_count = kSecondary;
  c.seed = seed;
  return c;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

class RayBatchesTest : public testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    scene_ = test::load_test_scene(GetParam());
    bvh_ = make_gpu_layout(build_bvh(scene_), scene_);
  }
  Scene scene_;
  GpuBvh bvh_;
};

TEST_P(RayBatchesTest, DeterministicForASeedAndThreadCount) {
  RayBatchConfig c = small_config();
  c.jitter = true;
  const RayBatches a = make_ray_batches(scene_, bvh_, c);
  c.threads = 1;
  const RayBatches b = make_ray_batches(scene_, bvh_, c);
  EXPECT_TRUE(same_bytes(a.primary, b.primary));
  EXPECT_TRUE(same_bytes(a.primary_hits, b.primary_hits));
  EXPECT_TRUE(same_bytes(a.ao.rays, b.ao.rays));
  EXPECT_TRUE(same_bytes(a.diffuse.rays, b.diffuse.rays));
  c.seed = 8;
  const RayBatches d = make_ray_batches(scene_, bvh_, c);
  EXPECT_FALSE(same_bytes(a.primary, d.primary));
  EXPECT_FALSE(same_bytes(a.ao.rays, d.ao.rays));
  EXPECT_FALSE(same_bytes(a.diffuse.rays, d.diffuse.rays));
}

TEST_P(RayBatchesTest, CountsCameraOriginsAndTmax) {
  const RayBatches b = make_ray_batches(scene_, bvh_, small_config());
  ASSERT_EQ(b.primary.size(), std::size_t{kWidth} * kHeight);
  ASSERT_EQ(b.primary_hits.size(), b.primary.size());
  ASSERT_GT(b.primary_hit_count, 0u);
  EXPECT_EQ(b.ao.rays.size(), kSecondary);
  EXPECT_EQ(b.diffuse.rays.size(), kSecondary);
  EXPECT_EQ(b.ao.source_prim.size(), kSecondary);

  const glm::vec3 eye = scene_.cameras[0].position;
  for (const gpu::Ray& r : b.primary) {
    ASSERT_EQ(r.origin, eye);
    ASSERT_EQ(r.tmin, 0.0f);
    ASSERT_EQ(r.tmax, std::numeric_limits<float>::infinity());
    ASSERT_NEAR(glm::length(r.dir), 1.0f, 1e-5f);
    ASSERT_GT(glm::dot(r.dir, scene_.cameras[0].forward), 0.0f);
  }
  // The centre pixel of an even grid sits just off the view axis; the middle ray is close to it.
  const gpu::Ray& mid = b.primary[(kHeight / 2) * kWidth + kWidth / 2];
  EXPECT_GT(glm::dot(mid.dir, glm::normalize(scene_.cameras[0].forward)), 0.99f);

  const float diagonal = glm::length(bvh_.bounds.extent());
  EXPECT_FLOAT_EQ(b.scene_diagonal, diagonal);
  EXPECT_FLOAT_EQ(b.ao_tmax, 0.1f * diagonal);
  for (const gpu::Ray& r : b.ao.rays) {
    ASSERT_EQ(r.tmax, b.ao_tmax);
    ASSERT_EQ(r.tmin, 0.0f);
  }
  for (const gpu::Ray& r : b.diffuse.rays) ASSERT_EQ(r.tmax, std::numeric_limits<float>::infinity());

  // Secondary ray i starts at the (i mod hits)-th primary hit, in pixel order.
  std::vector<int> hit_prims;
  for (const gpu::Hit& h : b.primary_hits)
    if (h.prim >= 0) hit_prims.push_back(h.prim);
  ASSERT_EQ(hit_prims.size(), b.primary_hit_count);
  for (std::size_t i = 0; i < kSecondary; i += 97)
    ASSERT_EQ(b.ao.source_prim[i], hit_prims[i % hit_prims.size()]);
  EXPECT_EQ(b.ao.source_prim, b.diffuse.source_prim);
}

TEST_P(RayBatchesTest, PrimaryHitsAreTheReference) {
  const RayBatches b = make_ray_batches(scene_, bvh_, small_config());
  for (std::size_t i = 0; i < b.primary.size(); i += 13) {
    const gpu::Hit h = trace_closest(bvh_, b.primary[i]);
    ASSERT_EQ(h.prim, b.primary_hits[i].prim);
    ASSERT_EQ(h.t, b.primary_hits[i].t);
  }
}

TEST_P(RayBatchesTest, SecondaryRaysLeaveTheSurfaceOnTheRaySide) {
  const RayBatches b = make_ray_batches(scene_, bvh_, small_config());
  int ao_self = 0, diffuse_self = 0;
  for (const SecondaryRays* batch : {&b.ao, &b.diffuse}) {
    for (std::size_t i = 0; i < batch->rays.size(); i += 7) {  // a ~2,900-ray sample per batch
      const gpu::Ray& r = batch->rays[i];
      const int source = batch->source_prim[i];
      const Triangle& tri = scene_.triangles[static_cast<std::size_t>(source)];
      // The direction is in the hemisphere of the normal facing the primary ray, and the origin
      // lies on that side of the triangle's plane.
      const glm::vec3 c = glm::cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
      const float side = glm::dot(glm::normalize(c), r.dir);
      ASSERT_NE(side, 0.0f);
      const double plane = glm::dot(glm::dvec3(glm::normalize(c)),
                                    glm::dvec3(r.origin) - glm::dvec3(tri.v0));
      ASSERT_GT(plane * side, 0.0) << "ray " << i << " starts behind the triangle it leaves";
      ASSERT_NEAR(glm::length(r.dir), 1.0f, 1e-5f);
      // No self-intersection: the closest hit is never the triangle just left.
      gpu::Ray unbounded = r;
      unbounded.tmax = std::numeric_limits<float>::infinity();
      const gpu::Hit h = trace_closest(bvh_, unbounded);
      if (h.prim == source) ++(batch == &b.ao ? ao_self : diffuse_self);
    }
  }
  EXPECT_EQ(ao_self, 0);
  EXPECT_EQ(diffuse_self, 0);
}

INSTANTIATE_TEST_SUITE_P(Scenes, RayBatchesTest,
                         testing::Values("builtin:cornell", "meshes/utah_teapot.glb"),
                         test::scene_param_name);

TEST(RayBatches, CycleOverHitsAndEmptyWhenNothingHits) {
  const Scene scene = load_scene("builtin:cornell");
  std::vector<gpu::Ray> primaries(3, gpu::Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, 1.0f});
  std::vector<gpu::Hit> misses(3, kMiss);
  EXPECT_TRUE(make_secondary_rays(scene, primaries, misses, RayKind::kAo, 10, 1.0f, 1).rays.empty());
  std::vector<gpu::Hit> hits = misses;
  hits[1] = {5, 1.0f, 0.25f, 0.25f};
  const SecondaryRays s = make_secondary_rays(scene, primaries, hits, RayKind::kDiffuse, 10, 1.0f, 1);
  ASSERT_EQ(s.rays.size(), 10u);
  for (int p : s.source_prim) EXPECT_EQ(p, 5);
  for (const gpu::Ray& r : s.rays) EXPECT_EQ(r.origin, s.rays[0].origin);
}

// rays_of_kind hands out each kind's own batch; ray_kind_named inverts ray_kind_name.
TEST(RayBatches, KindsSelectTheirBatchAndNamesRoundTrip) {
  const Scene scene = load_scene("builtin:cornell");
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  RayBatchConfig c = small_config();
  c.secondary_count = 1000;
  const RayBatches b = make_ray_batches(scene, bvh, c);
  const std::pair<RayKind, const std::vector<gpu::Ray>*> batches[] = {
      {RayKind::kPrimary, &b.primary}, {RayKind::kAo, &b.ao.rays}, {RayKind::kDiffuse, &b.diffuse.rays}};
  for (const auto& [kind, rays] : batches) {
    ASSERT_FALSE(rays->empty()) << ray_kind_name(kind);
    EXPECT_EQ(rays_of_kind(b, kind).data(), rays->data()) << ray_kind_name(kind);
    EXPECT_EQ(rays_of_kind(b, kind).size(), rays->size()) << ray_kind_name(kind);
    EXPECT_EQ(ray_kind_named(ray_kind_name(kind)), kind);
  }
  EXPECT_FALSE(ray_kind_named("shadow").has_value());
  EXPECT_FALSE(ray_kind_named("").has_value());
}

TEST(RayBatches, JitterStaysInsideThePixel) {
  Camera cam;
  const auto centred = make_primary_rays(cam, 4, 4, false, 3);
  const auto jittered = make_primary_rays(cam, 4, 4, true, 3);
  ASSERT_EQ(centred.size(), 16u);
  for (std::size_t i = 0; i < 16; ++i) {
    EXPECT_NE(centred[i].dir, jittered[i].dir);
    // Within half a pixel (of a 4-pixel-wide view) of the centre ray.
    EXPECT_GT(glm::dot(centred[i].dir, jittered[i].dir), std::cos(cam.yfov / 4.0f));
  }
}

TEST(OffsetRay, MovesTowardsTheNormalAtEveryScale) {
  const glm::vec3 normals[] = {{0, 0, 1}, {0, 0, -1}, glm::normalize(glm::vec3(1, -2, 3)),
                               glm::normalize(glm::vec3(-1, 1, -1))};
  const float scales[] = {0.0f, 1e-3f, 0.02f, 1.0f, -7.5f, 1e3f, -1e5f};
  for (const glm::vec3& n : normals) {
    for (float s : scales) {
      const glm::vec3 p(s, -s, 0.5f * s);
      const glm::vec3 q = offset_ray_origin(p, n);
      EXPECT_GT(glm::dot(glm::dvec3(q) - glm::dvec3(p), glm::dvec3(n)), 0.0)
          << "scale " << s << " normal " << n.x << " " << n.y << " " << n.z;
      // Small: a few hundred ULPs, or 1/65536 near the origin.
      EXPECT_LT(glm::length(q - p), 1e-4f * std::max(1.0f, std::fabs(s)));
    }
  }
}

TEST(OffsetRay, FacingNormalAndBarycentricPoint) {
  const Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};  // normal +z
  EXPECT_EQ(facing_normal(t, {0, 0, -1}), glm::vec3(0, 0, 1));
  EXPECT_EQ(facing_normal(t, {0, 0, 1}), glm::vec3(0, 0, -1));
  EXPECT_EQ(barycentric_point(t, 0.25f, 0.5f), glm::vec3(0.25f, 0.5f, 0.0f));
  EXPECT_EQ(facing_normal(Triangle{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, {0, 0, 1}), glm::vec3(0.0f));
}

}  // namespace
}  // namespace hrpp
