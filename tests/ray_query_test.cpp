// host/gpu/ray_query_tracer: the driver's traversal (VK_KHR_ray_query) against two independent
// witnesses, the CPU reference (trace/cpu_traversal.h) and Embree (when the build has it), on
// every batch kind of the stand-ins: the same triangle, or another at the same t (a tie: the
// driver's triangle test rounds its own way), every miss a miss, under 0.1% of the rays
// otherwise. On the extreme cases secondary rays never hit the surface they leave and NaN/Inf/
// zero rays miss (the driver's leaks at shared edges are printed); negative tmin is refused.
// Renders of the Cornell boxes and the stand-ins agree with the compute tracer's. With the HRPP
// stage in front (exact mode) the answers are HRPP off's and shadow rays skip the query. A device
// without the extension is refused with one line (where a second driver without it is
// installed), and a context without ray queries cannot build. Skipped where the device lacks
// ray queries. The validation layer reports nothing.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "cli_runner.h"
#include "common/error.h"
#include "extreme_cases.h"
#include "front/make_device_tracer.h"
#include "front/gpu_predictor.h"
#include "gpu/ray_query_tracer.h"
#include "gpu_test_context.h"
#include "reference/embree_tracer.h"
#include "render/wavefront_renderer.h"
#include "test_scenes.h"
#include "trace/cpu_traversal.h"
#include "vk/vulkan_context.h"

namespace hrpp {
namespace {

// The binary's context with ray queries on, or nullptr where the device has none.
VulkanContext* ray_query_context() {
  static std::unique_ptr<VulkanContext> ctx = [] {
    if (!test::context().info().ray_query) return std::unique_ptr<VulkanContext>();
    VulkanOptions o;
    o.validate = true;
    o.ray_query = true;
    return std::make_unique<VulkanContext>(o);
  }();
  return ctx.get();
}

#define REQUIRE_RAY_QUERIES()                                                         \
  if (!ray_query_context())                                                           \
  GTEST_SKIP() << test::context().info().summary() << " has no VK_KHR_ray_query"

struct Tally {
  std::size_t rays = 0, ties = 0, disagreements = 0;
};

// The driver's answers against a witness's: occlusion equal; closest hits the same triangle
// or a tie, t within 1e-5 relative plus 1e-7 of the diagonal; with `barycentrics`, those of the
// same triangle within 1e-3.
Tally compare(std::span<const gpu::Ray> rays, std::span<const gpu::Hit> got,
              std::span<const gpu::Hit> want, QueryKind kind, const std::string& what,
              float diagonal, bool barycentrics = true) {
  Tally tally;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ++tally.rays;
    const gpu::Hit& g = got[i];
    const gpu::Hit& w = want[i];
    bool ok;
    if (kind == QueryKind::kAny || g.prim < 0 || w.prim < 0) {
      ok = (g.prim >= 0) == (w.prim >= 0) && (kind == QueryKind::kAny || g.prim == w.prim);
    } else {
      ok = std::fabs(g.t - w.t) <= 1e-5f * std::fabs(w.t) + 1e-7f * diagonal;
      if (ok && g.prim != w.prim) ++tally.ties;
      if (ok && barycentrics && g.prim == w.prim) {
        EXPECT_NEAR(g.u, w.u, 1e-3f) << what << " ray " << i;
        EXPECT_NEAR(g.v, w.v, 1e-3f) << what << " ray " << i;
      }
    }
    if (!ok && ++tally.disagreements <= 5)
      std::printf("  %s ray %zu: ray query prim %d t %.9g, witness prim %d t %.9g\n",
                  what.c_str(), i, g.prim, g.t, w.prim, w.t);
  }
  std::printf("%s: %zu rays, %zu ties, %zu disagreements\n", what.c_str(), tally.rays, tally.ties,
              tally.disagreements);
  return tally;
}

class RayQueryVsWitnesses : public testing::TestWithParam<std::string> {};

TEST_P(RayQueryVsWitnesses, SameHitsOnEveryBatchKind) {
  REQUIRE_RAY_QUERIES();
  const Scene scene = test::load_test_scene(GetParam());
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  RayQueryTracer tracer(*ray_query_context(), bvh);
  const RayBatches b = test::small_ray_batches(scene, bvh, 64, 4096);
  std::unique_ptr<EmbreeTracer> embree;
  if (embree_available()) embree = std::make_unique<EmbreeTracer>(scene);
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
    const GpuTraceResult got = tracer.trace(k.rays, k.kind);
    ASSERT_EQ(got.counters.rays, k.rays.size());
    std::vector<std::pair<std::string, std::vector<gpu::Hit>>> witnesses;
    witnesses.emplace_back("reference", trace_batch_cpu(bvh, k.rays, k.kind));
    if (embree) witnesses.emplace_back("embree", embree->trace(k.rays, k.kind));
    for (const auto& [name, want] : witnesses) {
      const Tally t = compare(k.rays, got.hits, want, k.kind, std::string(k.what) + " vs " + name,
                              b.scene_diagonal);
      EXPECT_LT(static_cast<double>(t.disagreements), 0.001 * static_cast<double>(t.rays))
          << k.what << " vs " << name;
    }
    std::uint64_t hits = 0;
    for (const gpu::Hit& h : got.hits) hits += h.prim >= 0 ? 1 : 0;
    EXPECT_EQ(got.counters.hits, hits) << k.what;
  }
  EXPECT_GT(tracer.structure().bytes, 0u);
  EXPECT_LE(tracer.structure().bytes, tracer.structure().uncompacted_bytes);
  EXPECT_EQ(ray_query_context()->validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Scenes, RayQueryVsWitnesses,
                         testing::Values("builtin:cornell", "meshes/utah_teapot.glb",
                                         "meshes/mcguire_bunny.glb"),
                         test::scene_param_name);

class RayQueryExtremes : public testing::TestWithParam<test::Frame> {};

// The extreme cases. The driver's triangle test is its own: on lavapipe it is not watertight
// (rays through shared vertices and edges can pass between triangles, and origins on a surface
// miss the t = 0 hit the reference counts), so its disagreements with the reference and its
// escapes from closed meshes are printed, not held to zero (docs/DEVICES.md, "Ray queries").
// What the tracer itself guarantees is checked: secondary rays never hit the surface they leave,
// occlusion agrees with the closest hit, and invalid rays miss. (Barycentrics on the tiny
// triangles are the driver's precision: 0.625 for 0.5 at 1e-11 across.)
TEST_P(RayQueryExtremes, KeepTheTracersOwnRules) {
  REQUIRE_RAY_QUERIES();
  const test::ExtremeScene x = test::make_extreme_scene(GetParam(), false);
  const GpuBvh bvh = make_gpu_layout(build_bvh(x.scene), x.scene);
  RayQueryTracer tracer(*ray_query_context(), bvh);
  const float diagonal = glm::length(bvh.bounds.hi - bvh.bounds.lo);
  for (const test::RayGroup& g : x.groups) {
    const GpuTraceResult closest = tracer.trace(g.rays, QueryKind::kClosest);
    const GpuTraceResult any = tracer.trace(g.rays, QueryKind::kAny);
    const std::string what = GetParam().name + " " + g.name;
    compare(g.rays, closest.hits, trace_batch_cpu(bvh, g.rays, QueryKind::kClosest),
            QueryKind::kClosest, what, diagonal, false);
    int escapes = 0, self_hits = 0, occlusion_differs = 0;
    for (std::size_t i = 0; i < g.rays.size(); ++i) {
      const gpu::Hit& h = closest.hits[i];
      const bool in_range = h.prim >= g.first && h.prim < g.last;
      escapes += g.rule == test::RayGroup::Rule::kHitRange && !in_range;
      self_hits += g.rule == test::RayGroup::Rule::kAvoidRange && in_range;
      occlusion_differs += (h.prim >= 0) != (any.hits[i].prim >= 0);
    }
    EXPECT_EQ(self_hits, 0) << what;
    EXPECT_EQ(occlusion_differs, 0) << what;
    if (g.rule == test::RayGroup::Rule::kHitRange)
      std::printf("%s: %d of %zu rays escape their mesh or hit another triangle first\n",
                  what.c_str(), escapes, g.rays.size());
  }
  const std::vector<gpu::Ray> invalid = test::invalid_rays(bvh.bounds.center());
  for (QueryKind kind : kQueryKinds)
    for (const gpu::Hit& h : tracer.trace(invalid, kind).hits) EXPECT_LT(h.prim, 0);
  EXPECT_EQ(ray_query_context()->validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Frames, RayQueryExtremes, testing::ValuesIn(test::extreme_frames()),
                         test::frame_param_name<testing::TestParamInfo<test::Frame>>);

// RMS of the per-value difference of two images.
double rms_difference(const std::vector<float>& a, const std::vector<float>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (double{a[i]} - b[i]) * (double{a[i]} - b[i]);
  return std::sqrt(s / static_cast<double>(a.size()));
}

class RayQueryRenders : public testing::TestWithParam<std::string> {};

// The same seed's image with each tracer differs by less than a tenth of the noise floor: the
// difference between two seeds' images with the compute tracer. Nearly every path takes the same
// triangles; the driver's t and barycentrics round differently.
TEST_P(RayQueryRenders, AgreeWithTheComputeTracersWithinTheNoiseFloor) {
  REQUIRE_RAY_QUERIES();
  const Scene scene = test::load_test_scene(GetParam());
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  RenderConfig config;
  config.width = config.height = 48;
  config.spp = 2;
  const auto render = [&](DeviceTracerKind tracer, std::uint32_t seed) {
    RenderConfig c = config;
    c.device_tracer = tracer;
    c.seed = seed;
    WavefrontRenderer r(*ray_query_context(), scene, bvh, c);
    return r.render().rgb;
  };
  const std::vector<float> compute = render(DeviceTracerKind::kCompute, 1);
  const std::vector<float> driver = render(DeviceTracerKind::kRayQuery, 1);
  const double floor = rms_difference(compute, render(DeviceTracerKind::kCompute, 2));
  const double diff = rms_difference(compute, driver);
  std::printf("%s: rms difference %.3g, noise floor (two seeds) %.3g\n", GetParam().c_str(), diff,
              floor);
  EXPECT_GT(floor, 0.0);
  EXPECT_LT(diff, 0.1 * floor);
  EXPECT_EQ(ray_query_context()->validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Scenes, RayQueryRenders, testing::ValuesIn(test::reference_scene_names()),
                         test::scene_param_name);

// HRPP in front of the driver's traversal, exact mode: the answers are HRPP off's (a verified
// closest hit comes from the project's triangle test, so the same triangle or a tie within the
// tolerance above; occlusion exactly), and prediction does answer rays: shadow rays without a
// query, camera rays with a shortened tmax (the second trace of a batch, its table warm).
TEST(RayQueryHrpp, ExactModeKeepsTheAnswersAndAnswersRaysWithoutAQuery) {
  REQUIRE_RAY_QUERIES();
  const Scene scene = test::load_test_scene("meshes/mcguire_bunny.glb");
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  const RayBatches b = test::small_ray_batches(scene, bvh, 64, 4096);
  PredictorConfig predictor;
  predictor.enabled = true;
  predictor.mode = PredictorMode::kExact;
  predictor.fallback = Fallback::kRoot;
  RayQueryTracer off(*ray_query_context(), bvh);
  const auto on = make_device_tracer(*ray_query_context(), DeviceTracerKind::kRayQuery, bvh, {}, predictor);
  ASSERT_NE(on->predictor(), nullptr);
  for (const auto& [rays, kind] : {std::pair{std::span<const gpu::Ray>(b.primary), QueryKind::kClosest},
                                   std::pair{std::span<const gpu::Ray>(b.ao.rays), QueryKind::kAny}}) {
    const std::string what = std::string("bunny ") + query_kind_name(kind) + " with HRPP";
    on->trace(rays, kind);  // fills the table
    const GpuTraceResult predicted = on->trace(rays, kind);
    const GpuTraceResult plain = off.trace(rays, kind);
    ASSERT_TRUE(predicted.predicted) << what;
    const Tally t = compare(rays, predicted.hits, plain.hits, kind, what, b.scene_diagonal);
    EXPECT_EQ(t.disagreements, 0u) << what;
    const std::uint64_t probes = predicted.predictor.c[HRPP_PC_PROBES];
    const std::uint64_t true_positives = predicted.predictor.c[HRPP_PC_TRUE_POSITIVES];
    EXPECT_EQ(probes, rays.size()) << what;
    EXPECT_GT(true_positives, rays.size() / 50) << what;
    const std::uint64_t without_query = predicted.counters.rays - predicted.traced;
    std::printf("%s: %llu true positives of %zu rays, %llu answered without a query\n",
                what.c_str(), static_cast<unsigned long long>(true_positives), rays.size(),
                static_cast<unsigned long long>(without_query));
    // Exact hit-all: every true positive still queries, its tmax shortened; hit-any: none does.
    EXPECT_EQ(without_query, kind == QueryKind::kAny ? true_positives : 0u) << what;
  }
  EXPECT_EQ(ray_query_context()->validation_messages(), 0u);
}

TEST(RayQuery, RefusesNegativeTminByName) {
  REQUIRE_RAY_QUERIES();
  const Scene scene = load_scene("builtin:cornell");
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  RayQueryTracer tracer(*ray_query_context(), bvh);
  std::vector<gpu::Ray> rays(3, gpu::Ray{bvh.bounds.center(), 0.0f, {0, 0, 1}, 1e30f});
  rays[2].tmin = -1.0f;
  try {
    tracer.trace(rays, QueryKind::kClosest);
    FAIL() << "a negative tmin was traced";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("ray 2 has tmin"), std::string::npos) << e.what();
  }
}

TEST(RayQuery, AContextWithoutRayQueriesCannotBuild) {
  const Scene scene = load_scene("builtin:cornell");
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
  EXPECT_THROW(RayQueryTracer(test::context(), bvh), Error);
}

// A second, older lavapipe (Mesa 22.3, no ray queries) where this machine has one: `hrpp trace
// --tracer rayquery` under it exits 1 with one line naming the extension.
class RayQueryCli : public test::CliTest {};

TEST_F(RayQueryCli, ADeviceWithoutTheExtensionIsRefusedWithOneLine) {
  const char* icd = std::getenv("HRPP_NO_RAY_QUERY_ICD");
  const std::string path = icd ? icd : "/opt/mesa22/lvp_icd.json";
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << "no driver without ray queries here (HRPP_NO_RAY_QUERY_ICD, " << path << ")";
  const std::filesystem::path rays = dir_ / "rays.bin";
  const gpu::Ray ray{{0, 0, -5}, 0.0f, {0, 0, 1}, 1e30f};
  std::ofstream(rays, std::ios::binary).write(reinterpret_cast<const char*>(&ray), sizeof ray);
  const test::CliResult r = test::run_command(
      "VK_DRIVER_FILES=" + path + " VK_ICD_FILENAMES=" + path + " " + HRPP_BINARY +
          " trace builtin:cornell --tracer rayquery --rays " + rays.string() + " --hits " +
          (dir_ / "hits.bin").string(),
      dir_);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("has no VK_KHR_ray_query"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "hits.bin"));
}

// Flags the ray-query tracer cannot honour end the command with one line naming the flag, before
// any device work.
TEST_F(RayQueryCli, BadCombinationsAreRefusedWithOneLine) {
  const std::filesystem::path rays = dir_ / "rays.bin";
  const gpu::Ray ray{{0, 0, -5}, 0.0f, {0, 0, 1}, 1e30f};
  std::ofstream(rays, std::ios::binary).write(reinterpret_cast<const char*>(&ray), sizeof ray);
  const std::string trace = "trace builtin:cornell --rays " + rays.string() + " --hits " +
                            (dir_ / "hits.bin").string() + " --tracer ";
  const std::filesystem::path skip = dir_ / "skip.json";
  std::ofstream(skip) << R"({"fallback": "skip"})";
  const std::pair<std::string, std::string> cases[] = {
      {trace + "bogus", "--tracer"},
      {trace + "rayquery --reorder morton", "--reorder"},
      {trace + "rayquery --bvh-nodes wide4", "--bvh-nodes"},
      {trace + "rayquery --count-steps", "--count-steps"},
      {trace + "rayquery --hrpp on --hrpp-config " + skip.string(), "fallback skip"},
      {"render --backend cpu --tracer rayquery --out " + (dir_ / "x.exr").string(), "--tracer"},
      {"render --tracer rayquery --reorder morton --out " + (dir_ / "x.exr").string(),
       "--reorder"}};
  for (const auto& [args, flag] : cases) {
    const test::CliResult r = run(args);
    EXPECT_EQ(r.status, 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find(flag), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "hits.bin")) << args;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "x.exr")) << args;
  }
}

}  // namespace
}  // namespace hrpp
