// host/front/gpu_ray_hash + shaders/lib/hrpp_hash.glsl: on the Vulkan device (lavapipe here) every
// hash kind at every precision gives the key of the C++ mirror (host/hrpp/ray_hash.h) bit for
// bit, on ~120k random rays (scene-like rays, shadow-like rays that end at a point in the box,
// and raw random float bits, tmax included: the light-space keys read it) plus a hand list of
// extreme floats (±0, subnormals, 2^-60 edges, ±max, ±Inf, NaNs with odd payloads and signs),
// over a normal and a flat scene box; the validation layer reports nothing.
#include <bit>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "front/gpu_ray_hash.h"
#include "vk/vulkan_context.h"
#include "gpu_test_context.h"
#include "hrpp/ray_hash.h"

namespace hrpp {
namespace {

using test::context;

float f(std::uint32_t bits) { return std::bit_cast<float>(bits); }

std::vector<float> extremes() {
  return {0.0f, -0.0f, f(1), f(0x80000001u), f(0x00400000u), f(0x807FFFFFu), f(0x00800000u),
          f(0x80800000u), 1.0f, -1.0f, 0.5f, -3.0f, 1e-30f, f(0x21800000u), f(0x217FFFFFu),
          f(0xA1800001u), std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
          std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
          f(0x7FC00000u), f(0xFFC00000u), f(0x7F800001u), f(0xFFFFFFFFu), f(0x7FA00000u),
          -1.25f, 2.75f, 3.0f, 1e30f, -1e-38f};
}

std::vector<gpu::Ray> test_rays(const Aabb& box) {
  std::vector<gpu::Ray> rays;
  const std::vector<float> ex = extremes();
  // Every extreme value in every component, the others ordinary.
  for (float v : ex)
    for (int c = 0; c < 7; ++c) {
      float x[7] = {0.25f, 1.5f, -0.75f, 0.6f, -0.3f, 0.74f, 1.7f};
      x[c] = v;
      rays.push_back({{x[0], x[1], x[2]}, 0.0f, {x[3], x[4], x[5]}, x[6]});
    }
  std::mt19937 rng(2024);
  std::uniform_int_distribution<std::size_t> pick(0, ex.size() - 1);
  for (int i = 0; i < 20000; ++i)  // components drawn from the extreme list
    rays.push_back({{ex[pick(rng)], ex[pick(rng)], ex[pick(rng)]},
                    0.0f,
                    {ex[pick(rng)], ex[pick(rng)], ex[pick(rng)]},
                    ex[pick(rng)]});
  std::uniform_int_distribution<std::uint32_t> bits;
  for (int i = 0; i < 30000; ++i)  // raw random float bits
    rays.push_back({{f(bits(rng)), f(bits(rng)), f(bits(rng))},
                    0.0f,
                    {f(bits(rng)), f(bits(rng)), f(bits(rng))},
                    f(bits(rng))});
  std::uniform_real_distribution<float> t(-0.1f, 1.1f), dir(-1.0f, 1.0f);
  const glm::vec3 e = box.extent();
  for (int i = 0; i < 50000; ++i) {  // scene-like: origins around the box, any direction
    const glm::vec3 o = box.lo + glm::vec3(t(rng), t(rng), t(rng)) * e;
    glm::vec3 d{dir(rng), dir(rng), dir(rng)};
    if (i % 7 == 0) d = glm::normalize(d);
    if (i % 11 == 0) d[i % 3] = 0.0f;  // axis-aligned planes: φ/θ bin edges
    rays.push_back({o, 0.0f, d, 1e30f});
  }
  for (int i = 0; i < 20000; ++i) {  // shadow-like: from a point to a point of the box
    const glm::vec3 o = box.lo + glm::vec3(t(rng), t(rng), t(rng)) * e;
    const glm::vec3 q = box.lo + glm::vec3(t(rng), t(rng), t(rng)) * e;
    if (i % 2 == 0) {
      rays.push_back({o, 0.0f, q - o, 0.999f});
    } else {
      const float len = glm::length(q - o);
      rays.push_back({o, 0.0f, (q - o) / len, len});
    }
  }
  return rays;
}

void expect_gpu_equals_mirror(const Aabb& box) {
  const std::vector<gpu::Ray> rays = test_rays(box);
  std::vector<HashConfig> configs;
  for (const Named<HashKind>& named : kHashKindNames)
    for (std::uint32_t n = 1; n <= HRPP_HASH_BITS_MAX; ++n) {
      configs.push_back({named.value, n});
      if (named.value == HashKind::kGridSpherical)  // direction bins of their own precision
        configs.push_back({named.value, n, HRPP_HASH_BITS_MAX + 1 - n});
    }
  for (const HashConfig& config : configs) {
    const HashKind kind = config.kind;
    const std::uint32_t n = config.bits;
    const gpu::HashParams params = make_hash_params(config, box);
    const std::vector<std::uint64_t> gpu_keys = hash_rays_on_gpu(context(), params, rays);
    ASSERT_EQ(gpu_keys.size(), rays.size());
    int mismatches = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const std::uint64_t cpu = hash_ray(rays[i].origin, rays[i].dir, rays[i].tmax, params);
      if (cpu == gpu_keys[i]) continue;
      if (++mismatches <= 5)
        ADD_FAILURE() << hash_kind_name(kind) << " N=" << n << " ray " << i << " o=("
                      << std::bit_cast<std::uint32_t>(rays[i].origin.x) << ","
                      << std::bit_cast<std::uint32_t>(rays[i].origin.y) << ","
                      << std::bit_cast<std::uint32_t>(rays[i].origin.z) << ") d=("
                      << std::bit_cast<std::uint32_t>(rays[i].dir.x) << ","
                      << std::bit_cast<std::uint32_t>(rays[i].dir.y) << ","
                      << std::bit_cast<std::uint32_t>(rays[i].dir.z) << ") tmax "
                      << std::bit_cast<std::uint32_t>(rays[i].tmax) << " cpu " << std::hex << cpu
                      << " gpu " << gpu_keys[i];
    }
    EXPECT_EQ(mismatches, 0) << hash_kind_name(kind) << " N=" << n << " D=" << config.dir_bits;
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

TEST(HashGpu, EqualsMirrorOnRandomAndExtremeRays) {
  expect_gpu_equals_mirror({{-1.25f, -0.5f, -2.0f}, {2.75f, 3.0f, 1.0f}});
}

TEST(HashGpu, EqualsMirrorOnAFlatSceneBox) {
  expect_gpu_equals_mirror({{-1.0f, 0.0f, -1.0f}, {1.0f, 0.0f, 1.0f}});  // a floor: y is flat
}

}  // namespace
}  // namespace hrpp
