// The trace kernels over 4-wide nodes (--bvh-nodes wide4 and wide4-float) on the Vulkan device
// (lavapipe here): their answers equal the CPU reference traversal's bit for bit (closest hit:
// same triangle, t, u, v; any hit: the same verdict), on the stand-ins' primary, AO and diffuse
// rays, through the indexed kernels of a sorted trace, and on the extreme-case and leak suites
// with their exact rules; a wide step covers more of the tree than a binary one (fewer loop
// steps); HRPP on refuses the formats with a one-line error; `hrpp bench` takes the option. The
// validation layer reports nothing.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "cli_runner.h"
#include "common/error.h"
#include "extreme_cases.h"
#include "front/make_device_tracer.h"
#include "gpu/gpu_tracer.h"
#include "gpu/ray_sorter.h"
#include "vk/vulkan_context.h"
#include "gpu_test_context.h"
#include "test_scenes.h"
#include "trace/cpu_traversal.h"
#include "trace/ray_batches.h"

namespace hrpp {
namespace {

using test::context;

GpuBvh wide(const Scene& scene, NodeFormat format = NodeFormat::kWide4) {
  return make_gpu_layout(build_bvh(scene), scene, NodeLayout::kDfs, format);
}

constexpr NodeFormat kWideFormats[] = {NodeFormat::kWide4, NodeFormat::kWide4Float};

// GPU closest and any hits over the wide nodes (sorted first with `sorter`) against the CPU
// reference over the binary ones; returns the number of rays that differ (the first few
// reported).
int count_differences(const GpuBvh& bvh, const std::vector<gpu::Ray>& rays,
                      const std::string& what, RaySorter* sorter = nullptr) {
  GpuTracer tracer(context(), bvh);
  const GpuTraceResult closest = tracer.trace(rays, QueryKind::kClosest, sorter);
  const GpuTraceResult any = tracer.trace(rays, QueryKind::kAny, sorter);
  int differ = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const gpu::Hit ref = trace_closest(bvh, rays[i]);
    const bool ok = test::same_hit(closest.hits[i], ref) &&
                    (any.hits[i].prim >= 0) == trace_any(bvh, rays[i]);
    if (!ok && ++differ <= 3)
      ADD_FAILURE() << what << " ray " << i << ": wide gpu " << closest.hits[i].prim << " t "
                    << closest.hits[i].t << ", cpu " << ref.prim << " t " << ref.t;
  }
  return differ;
}

class WideNodesGpu : public testing::TestWithParam<std::string> {};

TEST_P(WideNodesGpu, AnswersEqualTheCpuReference) {
  const Scene scene = test::load_test_scene(GetParam());
  const RayBatches b =
      test::small_ray_batches(scene, make_gpu_layout(build_bvh(scene), scene), 48, 2304);
  for (const NodeFormat f : kWideFormats) {
    SCOPED_TRACE(node_format_name(f));
    const GpuBvh bvh = wide(scene, f);
    EXPECT_EQ(count_differences(bvh, b.primary, "primary"), 0);
    EXPECT_EQ(count_differences(bvh, b.ao.rays, "ao"), 0);
    EXPECT_EQ(count_differences(bvh, b.diffuse.rays, "diffuse"), 0);
    RaySorter sorter(context(), bvh.bounds, b.diffuse.rays.size());
    EXPECT_EQ(count_differences(bvh, b.diffuse.rays, "diffuse, sorted", &sorter), 0);
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(StandIns, WideNodesGpu, testing::ValuesIn(test::reference_scene_names()),
                         test::scene_param_name);

// Fewer subgroup steps of the interior loop than over binary nodes, the same hits.
TEST(WideNodesGpuSteps, AWideStepCoversMoreOfTheTree) {
  const Scene scene = test::load_test_scene("meshes/mcguire_bunny.glb");
  const GpuBvh binary = make_gpu_layout(build_bvh(scene), scene);
  const RayBatches b = test::small_ray_batches(scene, binary, 32, 1024);
  GpuTracerConfig counting;
  counting.count_steps = true;
  GpuTracer on_binary(context(), binary, counting);
  for (const NodeFormat f : kWideFormats) {
    SCOPED_TRACE(node_format_name(f));
    GpuTracer on_wide(context(), wide(scene, f), counting);
    for (const std::vector<gpu::Ray>* rays : {&b.primary, &b.diffuse.rays}) {
      const GpuTraceResult w = on_wide.trace(*rays, QueryKind::kClosest),
                           n = on_binary.trace(*rays, QueryKind::kClosest);
      for (std::size_t i = 0; i < rays->size(); ++i) ASSERT_TRUE(test::same_hit(w.hits[i], n.hits[i]));
      EXPECT_GT(w.counters.interior_steps, 0u);
      EXPECT_LT(w.counters.interior_steps * 4, n.counters.interior_steps * 3);
      EXPECT_LT(w.counters.interior_visited * 4, n.counters.interior_visited * 3);
    }
  }
}

// The extreme-case suite (tests/extreme_cases.h) over wide nodes: the CPU reference's answers,
// and the exact rules (no escape from closed meshes, no self-hits) on the device's answers
// (without the huge triangle, as the suite checks them).
class ExtremeRaysWide : public testing::TestWithParam<test::Frame> {};

TEST_P(ExtremeRaysWide, EqualTheCpuReferenceAndKeepTheExactRules) {
  for (const bool huge : {false, true}) {
    const test::ExtremeScene x = test::make_extreme_scene(GetParam(), huge);
    for (const NodeFormat f : kWideFormats) {
      SCOPED_TRACE(node_format_name(f));
      const GpuBvh bvh = wide(x.scene, f);
      const std::vector<gpu::Ray> rays = test::extreme_rays(x, bvh.bounds.center());
      EXPECT_EQ(count_differences(bvh, rays, GetParam().name), 0) << huge;
      GpuTracer tracer(context(), bvh);
      EXPECT_EQ(test::count_extreme_failures(x, tracer.trace(rays, QueryKind::kClosest).hits), 0)
          << huge;
    }
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Frames, ExtremeRaysWide, testing::ValuesIn(test::extreme_frames()),
                         test::frame_param_name<testing::TestParamInfo<test::Frame>>);

// The leak suite (tests/extreme_cases.h) over wide nodes: the CPU reference's answers, and no
// ray from inside a closed mesh escapes it (rounded-outward boxes leave no gap).
class LeakRaysWide : public testing::TestWithParam<test::LeakFrame> {};

TEST_P(LeakRaysWide, EqualTheCpuReferenceAndNothingEscapes) {
  const test::LeakScene x = test::make_leak_scene(GetParam());
  const std::vector<gpu::Ray> rays = test::group_rays(x.groups);
  for (const NodeFormat f : kWideFormats) {
    SCOPED_TRACE(node_format_name(f));
    const GpuBvh bvh = wide(x.scene, f);
    EXPECT_EQ(count_differences(bvh, rays, GetParam().name), 0);
    GpuTracer tracer(context(), bvh);
    EXPECT_EQ(test::count_rule_breaks(x.groups, tracer.trace(rays, QueryKind::kClosest).hits), 0)
        << GetParam().name;  // escapes: the leak suite's groups hit their own mesh
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Frames, LeakRaysWide, testing::ValuesIn(test::leak_frames()),
                         test::frame_param_name<testing::TestParamInfo<test::LeakFrame>>);

TEST(WideNodesHrpp, HrppOnRefusesTheFormats) {
  for (const NodeFormat f : kWideFormats) {
    const GpuBvh bvh = wide(test::load_test_scene("builtin:cornell"), f);
    PredictorConfig p;
    p.enabled = true;
    try {
      make_device_tracer(context(), DeviceTracerKind::kCompute, bvh, {}, p);
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      const std::string flag = std::string("--bvh-nodes ") + node_format_name(f);
      EXPECT_NE(std::string(e.what()).find(flag), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("HRPP off"), std::string::npos) << e.what();
    }
  }
}

// `hrpp bench` over wide nodes: every tracer checked against the CPU reference (bench exits
// 1 on a mismatch); `hrpp render` with HRPP on says what to do and writes no image. (A bad
// value naming the flag: tests/bad_input_test.cpp.)
class WideNodesCli : public test::CliTest {};

TEST_F(WideNodesCli, BenchTracesWideNodesAndHrppOnSaysWhy) {
  for (const char* f : {"wide4", "wide4-float"}) {
    const test::CliResult r = run("bench teapot --rays 2048 --no-embree --repeat 1 "
                                  "--check-rays 2048 --bvh-nodes " + std::string(f));
    EXPECT_EQ(r.status, 0) << f << ": " << r.err;
  }
  const test::CliResult hrpp = run("render builtin:cornell --size 16x16 --spp 1 --hrpp on "
                                   "--bvh-nodes wide4 --out " + (dir_ / "wide.exr").string());
  EXPECT_NE(hrpp.status, 0);
  EXPECT_NE(hrpp.err.find("HRPP off only"), std::string::npos) << hrpp.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "wide.exr"));
}

}  // namespace
}  // namespace hrpp
