// host/gpu/ + shaders/trace_*.comp: on the Vulkan device (lavapipe here) the GPU closest and any
// hits equal the CPU reference traversal (host/trace/cpu_traversal.h) ray for ray, on primary,
// AO and diffuse rays over the Cornell box, the teapot and the bunny; counters are consistent;
// an exhausted loop budget is an error; the validation layer reports nothing.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "common/error.h"
#include "gpu/gpu_tracer.h"
#include "vk/memory_plan.h"
#include "vk/storage_buffer.h"
#include "vk/texel_view.h"
#include "vk/vulkan_context.h"
#include "gpu_test_context.h"
#include "test_scenes.h"
#include "trace/cpu_traversal.h"

namespace hrpp {
namespace {

constexpr int kSide = 64;                 // primary rays: kSide × kSide pixels
constexpr int kRaysPerKind = kSide * kSide;  // 4096 per kind, 4 kinds + edge cases > 16k rays

using test::context;

bool is_lavapipe() { return context().info().driver.find("llvmpipe") != std::string::npos; }

// Pinhole camera rays through a kSide × kSide grid.
std::vector<gpu::Ray> primary_rays(const Camera& cam) {
  const glm::vec3 right = glm::normalize(glm::cross(cam.forward, cam.up));
  const float h = std::tan(0.5f * cam.yfov);
  const float w = h * (cam.aspect > 0.0f ? cam.aspect : 1.0f);
  std::vector<gpu::Ray> rays;
  const float n = static_cast<float>(kSide);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const float sx = (2.0f * (static_cast<float>(x) + 0.5f) / n - 1.0f) * w;
      const float sy = (1.0f - 2.0f * (static_cast<float>(y) + 0.5f) / n) * h;
      gpu::Ray r;
      r.origin = cam.position;
      r.tmin = 0.0f;
      r.dir = glm::normalize(cam.forward + sx * right + sy * cam.up);
      r.tmax = std::numeric_limits<float>::infinity();
      rays.push_back(r);
    }
  return rays;
}

// Cosine-distributed rays leaving the surface points the primary rays hit (random triangles'
// points when few hit), offset along the geometric normal. ao: short rays (tmax = 10% of the
// scene diagonal), otherwise unbounded diffuse bounces.
std::vector<gpu::Ray> bounce_rays(const Scene& scene, const GpuBvh& bvh,
                                  const std::vector<gpu::Ray>& primary, bool ao,
                                  std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const float diag = glm::length(bvh.bounds.hi - bvh.bounds.lo);
  struct Point {
    glm::vec3 p, n;
  };
  std::vector<Point> points;
  for (const gpu::Ray& r : primary) {
    const gpu::Hit h = trace_closest(bvh, r);
    if (h.prim < 0) continue;
    const Triangle& t = scene.triangles[h.prim];
    glm::vec3 n = glm::normalize(glm::cross(t.v1 - t.v0, t.v2 - t.v0));
    if (glm::dot(n, r.dir) > 0.0f) n = -n;
    points.push_back({r.origin + h.t * r.dir, n});
  }
  while (points.size() < 64) {
    const Triangle& t = scene.triangles[rng() % scene.triangles.size()];
    const glm::vec3 c = glm::cross(t.v1 - t.v0, t.v2 - t.v0);
    if (glm::length(c) == 0.0f) continue;
    float a = u01(rng), b = u01(rng);
    if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
    points.push_back({t.v0 + a * (t.v1 - t.v0) + b * (t.v2 - t.v0), glm::normalize(c)});
  }
  std::vector<gpu::Ray> rays;
  for (int i = 0; i < kRaysPerKind; ++i) {
    const Point& pt = points[static_cast<std::size_t>(i) % points.size()];
    const glm::vec3 n = pt.n;
    const glm::vec3 t = glm::normalize(std::abs(n.x) > 0.5f ? glm::cross(n, glm::vec3(0, 1, 0))
                                                            : glm::cross(n, glm::vec3(1, 0, 0)));
    const glm::vec3 b = glm::cross(n, t);
    const float r1 = u01(rng), phi = 6.2831853f * u01(rng), s = std::sqrt(r1);
    gpu::Ray r;
    r.origin = pt.p + (1e-4f * diag) * n;
    r.tmin = 0.0f;
    r.dir = glm::normalize(s * std::cos(phi) * t + s * std::sin(phi) * b +
                           std::sqrt(std::max(0.0f, 1.0f - r1)) * n);
    r.tmax = ao ? 0.1f * diag : std::numeric_limits<float>::infinity();
    rays.push_back(r);
  }
  return rays;
}

// Rays from random points around the scene towards random points on random triangles: mostly
// hits, over every part of the tree (as in tests/traversal_test.cpp).
std::vector<gpu::Ray> targeted_rays(const Scene& scene, const GpuBvh& bvh, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const glm::vec3 ext = bvh.bounds.hi - bvh.bounds.lo;
  const glm::vec3 lo = bvh.bounds.lo - 0.25f * ext;
  std::vector<gpu::Ray> rays;
  for (int i = 0; i < kRaysPerKind; ++i) {
    const Triangle& t = scene.triangles[rng() % scene.triangles.size()];
    float a = u01(rng), b = u01(rng);
    if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
    gpu::Ray r;
    r.origin = lo + glm::vec3(u01(rng), u01(rng), u01(rng)) * (1.5f * ext);
    r.tmin = 0.0f;
    r.dir = t.v0 + a * (t.v1 - t.v0) + b * (t.v2 - t.v0) - r.origin;
    r.tmax = std::numeric_limits<float>::infinity();
    if (glm::length(r.dir) == 0.0f) r.dir = {0, 0, 1};
    rays.push_back(r);
  }
  return rays;
}

// Rays the semantics single out: invalid ones miss, axis-parallel ones use the ±2^80
// reciprocals, an empty interval (tmax < tmin) misses, a ray along a box face.
std::vector<gpu::Ray> edge_rays(const GpuBvh& bvh) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const glm::vec3 lo = bvh.bounds.lo, hi = bvh.bounds.hi, c = 0.5f * (lo + hi);
  const glm::vec3 before = c - glm::vec3(0, 0, 2.0f * (hi.z - lo.z) + 1.0f);
  return {
      {{nan, 0, 0}, 0, {0, 0, 1}, inf},         {before, 0, {nan, 0, 1}, inf},
      {before, 0, {0, 0, inf}, inf},            {before, 0, {0, 0, 0}, inf},
      {before, 0, {0, 0, 1}, nan},              {before, 5.0f, {0, 0, 1}, 1.0f},
      {before, 0, {0, 0, 1}, inf},              {before, 0, {0, 0, -1}, inf},
      {{c.x, lo.y, before.z}, 0, {0, 0, 1}, inf}, {{lo.x, lo.y, before.z}, 0, {0, 0, 1}, inf},
      {c, 0, {1, 0, 0}, inf},                   {c, 0, {0, -1e-30f, 1}, inf},
  };
}

struct Batch {
  std::string kind;
  std::vector<gpu::Ray> rays;
};

struct SceneData {
  Scene scene;
  GpuBvh bvh;
  std::vector<Batch> batches;
};

SceneData make_scene_data(const std::string& name) {
  SceneData d;
  d.scene = test::load_test_scene(name);
  d.bvh = make_gpu_layout(build_bvh(d.scene), d.scene);
  std::vector<gpu::Ray> primary = primary_rays(d.scene.cameras.at(0));
  d.batches.push_back({"ao", bounce_rays(d.scene, d.bvh, primary, true, 7)});
  d.batches.push_back({"diffuse", bounce_rays(d.scene, d.bvh, primary, false, 11)});
  d.batches.push_back({"primary", std::move(primary)});
  d.batches.push_back({"targeted", targeted_rays(d.scene, d.bvh, 13)});
  d.batches.push_back({"edge", edge_rays(d.bvh)});
  return d;
}

// Same prim, and the same t within 1e-6 relative (closest hit). The CPU and GPU evaluate the
// same operations, so t, u, v normally agree bit for bit; `exact` counts those.
struct Comparison {
  std::size_t mismatches = 0, exact = 0;
  std::string first;
};

Comparison compare_closest(const std::vector<gpu::Ray>& rays, const std::vector<gpu::Hit>& gpu,
                           const std::vector<gpu::Hit>& cpu) {
  Comparison c;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const gpu::Hit& g = gpu[i];
    const gpu::Hit& r = cpu[i];
    const bool same_t = r.prim < 0 || std::abs(g.t - r.t) <= 1e-6f * std::abs(r.t);
    if (g.prim != r.prim || !same_t) {
      if (c.mismatches++ == 0)
        c.first = "ray " + std::to_string(i) + ": gpu prim " + std::to_string(g.prim) + " t " +
                  std::to_string(g.t) + ", cpu prim " + std::to_string(r.prim) + " t " +
                  std::to_string(r.t);
      continue;
    }
    if (r.prim < 0 || (g.t == r.t && g.u == r.u && g.v == r.v)) ++c.exact;
  }
  return c;
}

class GpuTrace : public testing::TestWithParam<std::string> {};

TEST_P(GpuTrace, EqualsCpuReference) {
  const SceneData d = make_scene_data(GetParam());
  GpuTracer tracer(context(), d.bvh);
  std::size_t total = 0;
  for (const Batch& b : d.batches) {
    SCOPED_TRACE(b.kind);
    total += b.rays.size();
    std::vector<gpu::Hit> cpu_closest(b.rays.size());
    std::vector<char> cpu_any(b.rays.size());
    TraversalCounters cpu_counters;
    for (std::size_t i = 0; i < b.rays.size(); ++i) {
      cpu_closest[i] = trace_closest(d.bvh, b.rays[i], &cpu_counters);
      cpu_any[i] = trace_any(d.bvh, b.rays[i]);
    }

    const GpuTraceResult closest = tracer.trace(b.rays, QueryKind::kClosest);
    ASSERT_EQ(closest.hits.size(), b.rays.size());
    const Comparison c = compare_closest(b.rays, closest.hits, cpu_closest);
    EXPECT_EQ(c.mismatches, 0u) << c.first;
    EXPECT_EQ(c.exact, b.rays.size()) << "hits within 1e-6 but not bit-identical";
    EXPECT_EQ(closest.counters.rays, b.rays.size());
    EXPECT_EQ(closest.counters.hits, cpu_counters.hits);
    EXPECT_GE(closest.counters.triangles_tested, closest.counters.hits);
    EXPECT_GE(closest.counters.leaves_visited, closest.counters.hits);
    EXPECT_GT(closest.kernel_ms, 0.0);

    const GpuTraceResult any = tracer.trace(b.rays, QueryKind::kAny);
    std::size_t any_mismatch = 0, occluded = 0;
    for (std::size_t i = 0; i < b.rays.size(); ++i) {
      const gpu::Hit& h = any.hits[i];
      occluded += h.prim == 0;
      if (h.prim != (cpu_any[i] ? 0 : -1) || h.t != 0.0f || h.u != 0.0f || h.v != 0.0f)
        ++any_mismatch;
    }
    EXPECT_EQ(any_mismatch, 0u);
    EXPECT_EQ(any.counters.rays, b.rays.size());
    EXPECT_EQ(any.counters.hits, occluded);
    EXPECT_GE(any.counters.triangles_tested, any.counters.hits);
    // An any-hit query stops at its first hit: never more work than the closest-hit one.
    EXPECT_LE(any.counters.triangles_tested, closest.counters.triangles_tested);
    std::printf("%-8s %5zu rays: closest %llu hits (%zu bit-identical), any %zu occluded\n",
                b.kind.c_str(), b.rays.size(),
                static_cast<unsigned long long>(closest.counters.hits), c.exact, occluded);
  }
  EXPECT_GE(total, 10000u);
  EXPECT_EQ(context().validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Scenes, GpuTrace,
                         testing::Values("builtin:cornell", "meshes/utah_teapot.glb",
                                         "meshes/mcguire_bunny.glb"),
                         test::scene_param_name);

// Rays per invocation: 16 on a CPU device (lavapipe's loop limiter), 1 on a GPU, unless set.
TEST(GpuTracer, RaysPerInvocationDefaultsByDeviceType) {
  DeviceInfo cpu, gpu;
  cpu.type = VK_PHYSICAL_DEVICE_TYPE_CPU;
  gpu.type = VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU;
  const GpuTracerConfig unset;
  EXPECT_EQ(unset.rays_per_invocation, 0u);
  EXPECT_EQ(unset.resolved_for(cpu).rays_per_invocation, 16u);
  EXPECT_EQ(unset.resolved_for(gpu).rays_per_invocation, 1u);
  GpuTracerConfig set;
  set.rays_per_invocation = 4;
  EXPECT_EQ(set.resolved_for(cpu).rays_per_invocation, 4u);
  EXPECT_EQ(set.resolved_for(gpu).rays_per_invocation, 4u);
  // The tracer on this device runs what resolved_for names, and its chunks follow.
  const Scene scene = builtin_cornell();
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  const GpuTracer tracer(context(), bvh, unset);
  EXPECT_EQ(tracer.config().rays_per_invocation,
            unset.resolved_for(context().info()).rays_per_invocation);
  EXPECT_EQ(GpuTracer::max_dispatch_rays(context().info(), unset),
            GpuTracer::max_dispatch_rays(context().info(), tracer.config()));
}

TEST(GpuTracer, ChunksAndEmptyBatches) {
  const Scene scene = builtin_cornell();
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  GpuTracer tracer(context(), bvh, GpuTracerConfig{1});
  EXPECT_TRUE(tracer.trace({}, QueryKind::kClosest).hits.empty());
  const std::vector<gpu::Ray> rays = primary_rays(scene.cameras.at(0));
  const GpuTraceResult r =
      tracer.trace(rays, QueryKind::kClosest);  // 1 ray per invocation: 64 workgroups
  ASSERT_EQ(r.counters.rays, rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(r.hits[i].prim, trace_closest(bvh, rays[i]).prim);
  EXPECT_EQ(context().validation_messages(), 0u);
}

// GpuTracerConfig::count_steps: a kernel variant that also counts the interior-node loop's
// subgroup iterations. Its answers and work counts are the plain kernel's; at least one lane
// runs each step and at most all of them, so the lane use lies in [1 / subgroup size, 1]; the
// plain kernel counts no steps. Incoherent bounce rays use fewer lanes than primary rays.
TEST(GpuTracer, CountsTheInteriorLoopsSubgroupSteps) {
  const Scene scene = test::load_test_scene("meshes/mcguire_bunny.glb");
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  const std::vector<gpu::Ray> primary = primary_rays(scene.cameras.at(0));
  const std::vector<gpu::Ray> bounce = bounce_rays(scene, bvh, primary, false, 3);
  GpuTracer plain(context(), bvh);
  GpuTracerConfig counts;
  counts.count_steps = true;
  GpuTracer counting(context(), bvh, counts);
  const std::uint32_t lanes = context().info().subgroup_size;
  double use[2] = {0.0, 0.0};
  for (int k = 0; k < 2; ++k) {
    const std::vector<gpu::Ray>& rays = k == 0 ? primary : bounce;
    const GpuTraceResult a = plain.trace(rays, QueryKind::kClosest);
    const GpuTraceResult b = counting.trace(rays, QueryKind::kClosest);
    ASSERT_EQ(a.hits.size(), b.hits.size());
    EXPECT_EQ(std::memcmp(a.hits.data(), b.hits.data(), a.hits.size() * sizeof(gpu::Hit)), 0);
    EXPECT_EQ(a.counters.interior_visited, b.counters.interior_visited);
    EXPECT_EQ(a.counters.interior_steps, 0u);
    const TraversalCounters& c = b.counters;
    EXPECT_GT(c.interior_steps, 0u);
    EXPECT_LE(c.interior_steps, c.interior_visited);
    EXPECT_GE(c.interior_steps * lanes, c.interior_visited);
    use[k] = lane_use(c, lanes);
  }
  EXPECT_GT(use[0], use[1]) << "primary " << use[0] << ", bounce " << use[1];
  EXPECT_EQ(context().validation_messages(), 0u);
}

// Mesa 22's lavapipe ends a subgroup's loops after 65,535 iterations: one workgroup asked to
// trace every ray must be caught, not return a partial answer. A driver that runs the loops in
// full (Mesa 25's lavapipe does) must return every ray's right answer instead; the test then
// prints that there was no limiter to catch.
TEST(GpuTracer, ExhaustedLoopBudgetIsAnError) {
  if (!is_lavapipe()) GTEST_SKIP() << "only lavapipe has a loop limiter";
  const Scene scene = test::load_test_scene("meshes/mcguire_bunny.glb");
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  std::vector<gpu::Ray> rays = bounce_rays(scene, bvh, primary_rays(scene.cameras.at(0)), false, 3);
  while (rays.size() < 64u * 2048u) rays.insert(rays.end(), rays.begin(), rays.begin() + kRaysPerKind);
  GpuTracer tracer(context(), bvh, GpuTracerConfig{1u << 20});  // one workgroup for all rays
  try {
    const GpuTraceResult r = tracer.trace(rays, QueryKind::kClosest);
    EXPECT_EQ(context().validation_messages(), 0u);
    ASSERT_EQ(r.hits.size(), rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i)
      ASSERT_EQ(r.hits[i].prim, trace_closest(bvh, rays[i]).prim) << "ray " << i;
    std::printf("%s ran every loop in full: no loop limiter to catch\n",
                context().info().driver.c_str());
    return;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("loop limiter"), std::string::npos) << e.what();
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// One byte over the device's largest storage buffer: the error names the array and the limit
// that binds (lavapipe: maxStorageBufferRange; NVIDIA 580: maxMemoryAllocationSize, 2 MiB less).
TEST(StorageBuffer, OverTheLargestBufferNamesArrayAndLimit) {
  std::string name;
  const std::uint64_t limit =
      max_buffer_bytes(BufferBinding::kStorage, memory_limits(context().info()), &name);
  EXPECT_LE(limit, context().info().max_storage_buffer_range);
  try {
    StorageBuffer b(context(), static_cast<std::size_t>(limit) + 1, "test array");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("test array"), std::string::npos) << m;
    EXPECT_NE(m.find(name), std::string::npos) << m;
    EXPECT_NE(m.find(std::to_string(limit)), std::string::npos) << m;
  }
}

// The kernels read BVH and rays through 16-byte texels (vk/texel_view.h): an array that is not
// a whole number of texels is refused with its name, never read short.
TEST(TexelView, PartialTexelNamesArray) {
  StorageBuffer b(context(), 40, "odd array");
  try {
    TexelView v(context(), b);
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("odd array"), std::string::npos) << m;
    EXPECT_NE(m.find("16-byte texels"), std::string::npos) << m;
  }
  StorageBuffer whole(context(), 48, "whole array");
  TexelView v(context(), whole);
  EXPECT_NE(v.handle(), VK_NULL_HANDLE);
  EXPECT_EQ(context().validation_messages(), 0u);
}

TEST(VulkanContext, UnknownDeviceIsOneLineError) {
  try {
    VulkanContext ctx(VulkanOptions{"no-such-device-xyz", false});
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("no-such-device-xyz"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(VulkanContext, ReportsDeviceProperties) {
  const DeviceInfo& i = context().info();
  EXPECT_FALSE(i.name.empty());
  EXPECT_GT(i.subgroup_size, 0u);
  EXPECT_TRUE(i.float64);
  EXPECT_GE(i.max_storage_buffer_range, 1u << 27 >> 1);
  std::printf("device %s (%s), subgroup %u, float64 %d, int64 atomics %d, "
              "maxStorageBufferRange %llu, timestamp period %g ns\n",
              i.name.c_str(), i.type_name(), i.subgroup_size, i.float64, i.int64_atomics,
              static_cast<unsigned long long>(i.max_storage_buffer_range), i.timestamp_period_ns);
}

// The CLI: rays in, hits out; errors are one line and leave no output file.
std::string run(const std::string& args, const std::string& env = "") {
  const std::string cmd = env + " " + std::string(HRPP_BINARY) + " " + args + " 2>&1";
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  char buf[512];
  while (p && fgets(buf, sizeof buf, p)) out += buf;
  const int status = p ? pclose(p) : -1;
  return std::to_string(WEXITSTATUS(status)) + ":" + out;
}

TEST(TraceCli, WritesHitsMatchingTheTracer) {
  const Scene scene = builtin_cornell();
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  const std::vector<gpu::Ray> rays = primary_rays(scene.cameras.at(0));
  const std::string dir = testing::TempDir();
  const std::string rays_file = dir + "/gpu_trace_rays.bin", hits_file = dir + "/gpu_trace_hits.bin";
  {
    std::FILE* f = std::fopen(rays_file.c_str(), "wb");
    std::fwrite(rays.data(), sizeof(gpu::Ray), rays.size(), f);
    std::fclose(f);
  }
  const std::string out = run("trace --rays " + rays_file + " --hits " + hits_file + " --validate");
  ASSERT_EQ(out.substr(0, 2), "0:") << out;
  std::vector<gpu::Hit> hits(rays.size());
  std::FILE* f = std::fopen(hits_file.c_str(), "rb");
  ASSERT_TRUE(f);
  EXPECT_EQ(std::fread(hits.data(), sizeof(gpu::Hit), hits.size() + 1, f), hits.size());
  std::fclose(f);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const gpu::Hit h = trace_closest(bvh, rays[i]);
    ASSERT_EQ(hits[i].prim, h.prim);
    ASSERT_EQ(hits[i].t, h.t);
  }

  // A rays file of 33 bytes: one-line error, no hits file.
  std::remove(hits_file.c_str());
  f = std::fopen(rays_file.c_str(), "ab");
  std::fputc(0, f);
  std::fclose(f);
  const std::string bad = run("trace --rays " + rays_file + " --hits " + hits_file);
  EXPECT_EQ(bad.substr(0, 2), "1:") << bad;
  EXPECT_NE(bad.find("32-byte"), std::string::npos) << bad;
  EXPECT_EQ(std::count(bad.begin(), bad.end(), '\n'), 1) << bad;
  EXPECT_EQ(std::fopen(hits_file.c_str(), "rb"), nullptr);
}

TEST(TraceCli, NoVulkanDriverSaysWhatToInstall) {
  const std::string dir = testing::TempDir();
  const std::string rays_file = dir + "/gpu_trace_one_ray.bin";
  const gpu::Ray ray{{0, 0, 0}, 0, {0, 0, 1}, 1};
  std::FILE* f = std::fopen(rays_file.c_str(), "wb");
  std::fwrite(&ray, sizeof ray, 1, f);
  std::fclose(f);
  const std::string hits_file = dir + "/gpu_trace_none.bin";
  const std::string out = run("trace --rays " + rays_file + " --hits " + hits_file,
                              // HRPP_VALIDATE=0: the loader's own complaints would
                              // reach the validation messenger (CI sets it to 1)
                              "HRPP_VALIDATE=0 VK_DRIVER_FILES=/nonexistent.json "
                              "VK_ICD_FILENAMES=/nonexistent.json");
  EXPECT_EQ(out.substr(0, 2), "1:") << out;
  EXPECT_NE(out.find("mesa-vulkan-drivers"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  EXPECT_EQ(std::fopen(hits_file.c_str(), "rb"), nullptr);
}

}  // namespace
}  // namespace hrpp
