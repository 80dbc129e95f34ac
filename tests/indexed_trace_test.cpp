// The indexed trace kernels (shaders/trace_*_indexed.comp: HRPP_TRACE_INDEXED in
// shaders/lib/trace_kernel.glsl) on the Vulkan device (lavapipe here, under the validation
// layer): traced through a ray index list, every listed ray gets exactly the closest hit the
// plain kernel gives it (any hit: the same occlusion), written at its own index; unlisted
// rays' hits are untouched; the rays and hits counted are the plain kernel's (the visits too,
// in the plain kernel's order). Lists: identity, reversed, random permutations, a random
// subset, empty; counts of 1, around a subgroup and a workgroup (64 rays) and past a
// dispatch's first round of invocations.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "gpu/gpu_tracer.h"
#include "vk/storage_buffer.h"
#include "vk/texel_view.h"
#include "vk/vulkan_context.h"
#include "gpu_test_context.h"
#include "test_scenes.h"
#include "trace_interface.h"

namespace hrpp {
namespace {

using test::context;

// Bytes of a hit record no kernel writes: marks hits that were not traced.
constexpr std::uint32_t kUntouched = 0xABABABABu;

// Rays from points around the bounds towards points inside them, and some pointing away: hits
// and misses on every triangle side.
std::vector<gpu::Ray> rays_around(const Aabb& box, std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-0.3f, 1.3f), in(0.1f, 0.9f);
  std::vector<gpu::Ray> rays(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 from = box.lo + glm::vec3(u(rng), u(rng), u(rng)) * box.extent();
    const glm::vec3 to = box.lo + glm::vec3(in(rng), in(rng), in(rng)) * box.extent();
    const glm::vec3 d = i % 7 == 0 ? from - to : to - from;
    rays[i] = gpu::Ray{from, 0.0f, glm::normalize(d), 1e30f};
  }
  return rays;
}

struct Traced {
  std::vector<gpu::Hit> hits;  // the whole resident hit array
  TraversalCounters counters;
};

// Uploads `rays` into the tracer's resident array, marks every hit untouched and traces the
// first `count` positions: ray j, or with `list` the ray list[j] (the indexed kernel).
Traced trace_resident(GpuTracer& tracer, RayClass c, const std::vector<gpu::Ray>& rays,
                      std::uint32_t count, const std::vector<std::uint32_t>* list) {
  StorageBuffer& ray_array = tracer.ray_buffer(c, rays.size());
  if (!rays.empty()) ray_array.upload(rays.data(), rays.size() * sizeof(gpu::Ray));
  tracer.hit_buffer(c).fill(kUntouched);
  // The list as whole 16-byte texels, 4 entries each (at least one texel).
  std::vector<std::uint32_t> words;
  if (list) words = *list;
  words.resize(std::max<std::size_t>((words.size() + 3) / 4 * 4, 4), 0xFFFFFFFFu);
  StorageBuffer list_array(context(), words.size() * sizeof(std::uint32_t), "ray index list");
  list_array.upload(words.data(), words.size() * sizeof(std::uint32_t));
  const TexelView list_view(context(), list_array);
  tracer.begin(c);
  context().submit_and_wait(
      [&](VkCommandBuffer cmd) {
        tracer.record(cmd, c, count, nullptr, list ? &list_view : nullptr);
      },
      "indexed trace test");
  Traced out;
  out.counters = tracer.finish(c).counters;
  out.hits.resize(std::max<std::size_t>(rays.size(), 1));
  tracer.hit_buffer(c).download(out.hits.data(), out.hits.size() * sizeof(gpu::Hit));
  out.hits.resize(rays.size());
  return out;
}

// The answers of positions [0, n) equal: closest hit bit for bit; any hit as occluded or not
// (its record is the first occluder found, which a different visiting order may change).
::testing::AssertionResult same_answers(const std::vector<gpu::Hit>& a,
                                        const std::vector<gpu::Hit>& b, std::size_t first,
                                        std::size_t n, bool any_hit) {
  for (std::size_t i = first; i < first + n; ++i) {
    const bool same = any_hit ? (a[i].prim >= 0) == (b[i].prim >= 0)
                              : std::memcmp(&a[i], &b[i], sizeof(gpu::Hit)) == 0;
    if (!same)
      return ::testing::AssertionFailure()
             << "ray " << i << ": prim " << a[i].prim << " t " << a[i].t << " against prim "
             << b[i].prim << " t " << b[i].t;
  }
  return ::testing::AssertionSuccess();
}

bool untouched(const gpu::Hit& h) {
  std::uint32_t w[4];
  std::memcpy(w, &h, sizeof w);
  return std::all_of(std::begin(w), std::end(w), [](std::uint32_t x) { return x == kUntouched; });
}

// Rays and hits always agree. The visits too when the lanes hold the same rays (identity
// list): the speculative traversal's visits depend on a ray's neighbours in its subgroup
// (shaders/lib/traversal.glsl), so another order visits other nodes for the same answers.
void expect_same_counters(const TraversalCounters& a, const TraversalCounters& b,
                          bool same_lanes, const std::string& what) {
  EXPECT_EQ(a.rays, b.rays) << what;
  EXPECT_EQ(a.hits, b.hits) << what;
  if (!same_lanes) return;
  EXPECT_EQ(a.interior_visited, b.interior_visited) << what;
  EXPECT_EQ(a.leaves_visited, b.leaves_visited) << what;
  EXPECT_EQ(a.triangles_tested, b.triangles_tested) << what;
}

class IndexedTrace : public testing::Test {
 protected:
  void SetUp() override {
    scene_ = test::load_test_scene("meshes/utah_teapot.glb");
    bvh_ = make_gpu_layout(build_bvh(scene_, BvhConfig{}), scene_);
  }
  Scene scene_;
  GpuBvh bvh_;
};

// Permutations of every ray, at counts that fill no, part of or several subgroups and
// workgroups: the hits are the plain kernel's bit for bit, each at its own ray's index.
TEST_F(IndexedTrace, PermutationGivesThePlainKernelsHits) {
  GpuTracer tracer(context(), bvh_);
  const std::uint32_t per_group = HRPP_TRACE_WORKGROUP_SIZE;
  const std::uint32_t round = per_group * tracer.config().rays_per_invocation;
  std::mt19937 rng(5);
  for (std::uint32_t n : {1u, 7u, per_group - 1, per_group, per_group + 1, 1000u, round + 3}) {
    const std::vector<gpu::Ray> rays = rays_around(bvh_.bounds, n, n);
    std::vector<std::uint32_t> identity(n);
    std::iota(identity.begin(), identity.end(), 0u);
    std::vector<std::uint32_t> reversed(identity.rbegin(), identity.rend());
    std::vector<std::uint32_t> shuffled = identity;
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    for (RayClass c : {RayClass::kCamera, RayClass::kShadow}) {
      const Traced plain = trace_resident(tracer, c, rays, n, nullptr);
      if (n >= 1000) {
        EXPECT_GT(plain.counters.hits, 0u);
        EXPECT_LT(plain.counters.hits, n);
      }
      for (const auto* list : {&identity, &reversed, &shuffled}) {
        const std::string what = std::to_string(n) + " rays, " + ray_class_name(c) + ", list " +
                                 (list == &identity ? "identity" : list == &reversed ? "reversed"
                                                                                      : "random");
        const Traced indexed = trace_resident(tracer, c, rays, n, list);
        ASSERT_TRUE(same_answers(indexed.hits, plain.hits, 0, n, query_kind(c) == QueryKind::kAny))
            << what;
        expect_same_counters(indexed.counters, plain.counters, list == &identity, what);
      }
    }
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// A list naming some of the resident rays, out of order: those get their plain hits, the
// others' records are not written.
TEST_F(IndexedTrace, SubsetListWritesOnlyTheListedRays) {
  GpuTracer tracer(context(), bvh_);
  const std::vector<gpu::Ray> rays = rays_around(bvh_.bounds, 3000, 9);
  std::vector<std::uint32_t> all(rays.size());
  std::iota(all.begin(), all.end(), 0u);
  std::shuffle(all.begin(), all.end(), std::mt19937(2));
  const std::vector<std::uint32_t> some(all.begin(), all.begin() + 1111);
  for (RayClass c : {RayClass::kBounce, RayClass::kShadow}) {
    const auto count = static_cast<std::uint32_t>(rays.size());
    const Traced plain = trace_resident(tracer, c, rays, count, nullptr);
    const Traced indexed =
        trace_resident(tracer, c, rays, static_cast<std::uint32_t>(some.size()), &some);
    std::vector<bool> listed(rays.size(), false);
    for (std::uint32_t i : some) listed[i] = true;
    std::uint64_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      if (!listed[i]) {
        ASSERT_TRUE(untouched(indexed.hits[i])) << "unlisted ray " << i << " was written";
        continue;
      }
      ASSERT_TRUE(same_answers(indexed.hits, plain.hits, i, 1, query_kind(c) == QueryKind::kAny));
      hits += plain.hits[i].prim >= 0 ? 1 : 0;
    }
    EXPECT_EQ(indexed.counters.rays, some.size());
    EXPECT_EQ(indexed.counters.hits, hits);
    EXPECT_GT(hits, 0u);
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// No rays: nothing traced, nothing written, the completion check passes.
TEST_F(IndexedTrace, EmptyListTracesNothing) {
  GpuTracer tracer(context(), bvh_);
  const std::vector<gpu::Ray> rays = rays_around(bvh_.bounds, 10, 1);
  const std::vector<std::uint32_t> none;
  for (RayClass c : {RayClass::kCamera, RayClass::kShadow}) {
    const Traced t = trace_resident(tracer, c, rays, 0, &none);
    EXPECT_EQ(t.counters.rays, 0u);
    for (const gpu::Hit& h : t.hits) EXPECT_TRUE(untouched(h));
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

}  // namespace
}  // namespace hrpp
