// Extreme cases on the Vulkan device (lavapipe here), closest and any hit: the rays of
// tests/extreme_cases.h in every frame give the CPU reference's answers (same triangle, same t
// within 1e-6 relative), so the oracle's verdicts and the exact rules (no escapes from closed
// meshes, no fall-through, no self-hits of secondary rays) carry over; they are checked on the
// device's answers directly too. NaN/Inf/zero rays miss with HRPP off and on, and through
// `hrpp trace` (exit 0, every record a miss). The validation layer reports nothing.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "cli_runner.h"
#include "extreme_cases.h"
#include "front/make_device_tracer.h"
#include "gpu/gpu_tracer.h"
#include "vk/vulkan_context.h"
#include "gpu_test_context.h"
#include "hrpp/predictor_config.h"
#include "trace/cpu_traversal.h"

namespace hrpp {
namespace {

using test::RayGroup;

constexpr float kInfinity = std::numeric_limits<float>::infinity();

using test::context;

class ExtremeRaysGpu : public testing::TestWithParam<test::Frame> {};

// Closest and any hit of every ray on the device.
std::pair<GpuTraceResult, GpuTraceResult> trace_both(const GpuBvh& bvh,
                                                     const std::vector<gpu::Ray>& rays) {
  GpuTracer tracer(context(), bvh);
  std::pair<GpuTraceResult, GpuTraceResult> r{tracer.trace(rays, QueryKind::kClosest),
                                              tracer.trace(rays, QueryKind::kAny)};
  EXPECT_EQ(r.first.hits.size(), rays.size());
  EXPECT_EQ(r.second.hits.size(), rays.size());
  return r;
}

TEST_P(ExtremeRaysGpu, EqualsCpuReferenceAndKeepsTheExactRules) {
  const test::ExtremeScene x = test::make_extreme_scene(GetParam(), false);
  const GpuBvh bvh = make_gpu_layout(build_bvh(x.scene), x.scene);
  std::vector<gpu::Ray> rays = test::group_rays(x.groups);
  const std::vector<gpu::Ray> invalid = test::invalid_rays(bvh.bounds.center());
  rays.insert(rays.end(), invalid.begin(), invalid.end());
  const auto [closest, any] = trace_both(bvh, rays);

  std::size_t i = 0;
  for (const RayGroup& g : x.groups) {
    int differs = 0, rule_fails = 0;
    for (const gpu::Ray& ray : g.rays) {
      const gpu::Hit& h = closest.hits[i];
      const gpu::Hit ref = trace_closest(bvh, ray);
      const bool same_t = ref.prim < 0 || std::abs(h.t - ref.t) <= 1e-6f * std::abs(ref.t);
      if (h.prim != ref.prim || !same_t || (any.hits[i].prim >= 0) != trace_any(bvh, ray)) {
        if (++differs <= 3)
          ADD_FAILURE() << g.name << " ray " << i << ": gpu " << h.prim << " t " << h.t << ", cpu "
                        << ref.prim << " t " << ref.t;
      }
      const bool in_range = h.prim >= g.first && h.prim < g.last;
      if ((g.rule == RayGroup::Rule::kHitRange && !in_range) ||
          (g.rule == RayGroup::Rule::kAvoidRange && in_range))
        ++rule_fails;
      ++i;
    }
    EXPECT_EQ(differs, 0) << GetParam().name << " " << g.name;
    EXPECT_EQ(rule_fails, 0) << GetParam().name << " " << g.name;
    std::printf("%-15s %-15s %5zu rays: gpu != cpu %d, rule fails %d\n", GetParam().name.c_str(),
                g.name.c_str(), g.rays.size(), differs, rule_fails);
  }
  for (std::size_t k = 0; k < invalid.size(); ++k, ++i) {
    EXPECT_EQ(closest.hits[i].prim, -1) << "invalid ray " << k;
    EXPECT_EQ(any.hits[i].prim, -1) << "invalid ray " << k;
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Frames, ExtremeRaysGpu, testing::ValuesIn(test::extreme_frames()),
                         test::frame_param_name<testing::TestParamInfo<test::Frame>>);

// Leak suite (tests/extreme_cases.h) on the device: every answer equals the CPU reference's
// (same triangle, same t), and no ray from inside a closed mesh escapes it (box_on_face starts
// on the surface: there the CPU reference's answer is the rule).
class LeakRaysGpu : public testing::TestWithParam<test::LeakFrame> {};

TEST_P(LeakRaysGpu, EqualsCpuReferenceAndNothingEscapes) {
  const test::LeakScene x = test::make_leak_scene(GetParam());
  const GpuBvh bvh = make_gpu_layout(build_bvh(x.scene), x.scene);
  const std::vector<gpu::Ray> rays = test::group_rays(x.groups);
  const auto [closest, any] = trace_both(bvh, rays);
  std::size_t i = 0;
  for (const RayGroup& g : x.groups) {
    const bool inside = g.rule == RayGroup::Rule::kHitRange;
    int differs = 0, escapes = 0, any_escapes = 0;
    for (const gpu::Ray& ray : g.rays) {
      const gpu::Hit& h = closest.hits[i];
      const gpu::Hit ref = trace_closest(bvh, ray);
      if (h.prim != ref.prim || (ref.prim >= 0 && h.t != ref.t) ||
          (any.hits[i].prim >= 0) != trace_any(bvh, ray)) {
        if (++differs <= 3)
          ADD_FAILURE() << g.name << " ray " << i << ": gpu " << h.prim << " t " << h.t << ", cpu "
                        << ref.prim << " t " << ref.t;
      }
      escapes += inside && (h.prim < g.first || h.prim >= g.last);
      any_escapes += inside && any.hits[i].prim < 0;
      ++i;
    }
    EXPECT_EQ(differs, 0) << GetParam().name << " " << g.name;
    EXPECT_EQ(escapes, 0) << GetParam().name << " " << g.name;
    EXPECT_EQ(any_escapes, 0) << GetParam().name << " " << g.name << " (any hit)";
    std::printf("%-15s %-20s %6zu rays: gpu != cpu %d, escapes %d (any hit %d)\n",
                GetParam().name.c_str(), g.name.c_str(), g.rays.size(), differs, escapes,
                any_escapes);
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Frames, LeakRaysGpu, testing::ValuesIn(test::leak_frames()),
                         test::frame_param_name<testing::TestParamInfo<test::LeakFrame>>);

// Triangles 1e17..4e18 across (extreme_rays_test.cpp, HugeTriangles): the device's t is the
// CPU reference's, finite, bit for bit.
TEST(HugeTrianglesGpu, SameFiniteTAsTheCpuReference) {
  for (const float h : {1e17f, 1e18f, 4e18f}) {
    Scene scene;
    scene.name = "huge";
    scene.materials.emplace_back();
    scene.triangles = {{{-h, -h, -1e4f}, {h, -h, -1e4f}, {0.0f, h, -1e4f}}};
    scene.shading.emplace_back();
    const GpuBvh bvh = make_gpu_layout(build_bvh(scene), scene);
    std::vector<gpu::Ray> rays;
    for (const float z : {-9980.0f, 0.0f, 1e4f})
      rays.push_back({{0.3f, 0.2f, z}, 0.0f, {0.01f, -0.02f, -1.0f}, kInfinity});
    GpuTracer tracer(context(), bvh);
    const GpuTraceResult r = tracer.trace(rays, QueryKind::kClosest);
    for (std::size_t k = 0; k < rays.size(); ++k) {
      const gpu::Hit ref = trace_closest(bvh, rays[k]);
      ASSERT_EQ(ref.prim, 0) << h;
      EXPECT_TRUE(std::isfinite(ref.t)) << h;
      EXPECT_EQ(r.hits[k].prim, 0) << h;
      EXPECT_EQ(r.hits[k].t, ref.t) << h << " ray " << k;
    }
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// HRPP on (exact closest, any hit): invalid rays still miss and never hang the probe or the
// insert; valid rays keep the reference's answers.
TEST(ExtremeRaysGpuHrpp, InvalidRaysMissWithThePredictorOn) {
  const test::ExtremeScene x = test::make_extreme_scene(test::extreme_frames()[0], false);
  const GpuBvh bvh = make_gpu_layout(build_bvh(x.scene), x.scene);
  std::vector<gpu::Ray> rays = x.groups[0].rays;  // inside_sphere: all hit
  const std::vector<gpu::Ray> invalid = test::invalid_rays(bvh.bounds.center());
  for (int rep = 0; rep < 4; ++rep) rays.insert(rays.end(), invalid.begin(), invalid.end());
  PredictorConfig p;
  p.enabled = true;
  p.mode = PredictorMode::kExact;
  const auto tracer = make_device_tracer(context(), DeviceTracerKind::kCompute, bvh, {}, p);
  for (int pass = 0; pass < 2; ++pass) {  // the second pass probes a filled table
    const GpuTraceResult c = tracer->trace(rays, QueryKind::kClosest);
    const GpuTraceResult a = tracer->trace(rays, QueryKind::kAny);
    for (std::size_t k = 0; k < rays.size(); ++k) {
      const bool bad = k >= x.groups[0].rays.size();
      EXPECT_EQ(c.hits[k].prim, bad ? -1 : trace_closest(bvh, rays[k]).prim) << k;
      EXPECT_EQ(a.hits[k].prim >= 0, !bad) << k;
    }
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// `hrpp trace` on a file of NaN/Inf/zero rays: exit 0, every record a miss, with HRPP off and on.
class ExtremeTraceCli : public test::CliTest {};

TEST_F(ExtremeTraceCli, InvalidRaysGiveMissesNotErrors) {
  const std::vector<gpu::Ray> rays = test::invalid_rays({0.0f, 0.5f, 0.0f});
  const std::filesystem::path rays_file = dir_ / "r.bin", hits_file = dir_ / "h.bin";
  std::ofstream(rays_file, std::ios::binary)
      .write(reinterpret_cast<const char*>(rays.data()),
             static_cast<std::streamsize>(rays.size() * sizeof(gpu::Ray)));
  for (const std::string extra :
       {"", " --any-hit", " --hrpp on --hrpp-mode exact", " --any-hit --hrpp on"}) {
    const test::CliResult r = run("trace --rays " + rays_file.string() + " --hits " +
                                  hits_file.string() + " --validate" + extra);
    ASSERT_EQ(r.status, 0) << extra << ": " << r.err;
    std::vector<gpu::Hit> hits(rays.size());
    std::ifstream in(hits_file, std::ios::binary);
    ASSERT_TRUE(in.read(reinterpret_cast<char*>(hits.data()),
                        static_cast<std::streamsize>(hits.size() * sizeof(gpu::Hit))));
    for (const gpu::Hit& h : hits) EXPECT_EQ(h.prim, -1) << extra;
  }
}

}  // namespace
}  // namespace hrpp
