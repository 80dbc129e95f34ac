// Spatial-split BVHs (--bvh-splits spatial) on the Vulkan device (lavapipe here): the trace
// kernels' answers equal the CPU reference traversal over the same SBVH bit for bit and the
// object-split BVH's answers (closest hit: same triangle, t, u, v; any hit: the same verdict),
// on the stand-in scenes' primary, AO and diffuse rays and on the extreme-case and leak suites
// with their exact rules; HRPP keeps working with triangles in several leaves: exact answers
// equal HRPP off, and the CPU reference predictor reproduces the GPU's counters and hits;
// `hrpp bench` takes the option. The validation layer reports nothing.
#include <cstdio>
#include <string>
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
#include "hrpp/reference_predictor.h"
#include "test_scenes.h"
#include "trace/cpu_traversal.h"
#include "trace/ray_batches.h"

namespace hrpp {
namespace {

using test::context;

// GPU closest and any hits over the SBVH against the CPU reference over it and the GPU over
// the object BVH; returns the number of rays that differ anywhere (the first few reported).
int count_differences(const GpuBvh& object, const GpuBvh& split,
                      const std::vector<gpu::Ray>& rays, const std::string& what) {
  GpuTracer on_object(context(), object), on_split(context(), split);
  const GpuTraceResult oc = on_object.trace(rays, QueryKind::kClosest),
                       oa = on_object.trace(rays, QueryKind::kAny);
  const GpuTraceResult sc = on_split.trace(rays, QueryKind::kClosest),
                       sa = on_split.trace(rays, QueryKind::kAny);
  int differ = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const gpu::Hit ref = trace_closest(split, rays[i]);
    const bool ok = test::same_hit(sc.hits[i], ref) && test::same_hit(sc.hits[i], oc.hits[i]) &&
                    (sa.hits[i].prim >= 0) == trace_any(split, rays[i]) &&
                    (sa.hits[i].prim >= 0) == (oa.hits[i].prim >= 0);
    if (!ok && ++differ <= 3)
      ADD_FAILURE() << what << " ray " << i << ": sbvh gpu " << sc.hits[i].prim << " t "
                    << sc.hits[i].t << ", sbvh cpu " << ref.prim << " t " << ref.t
                    << ", object gpu " << oc.hits[i].prim << " t " << oc.hits[i].t;
  }
  return differ;
}

class SbvhGpu : public testing::TestWithParam<std::string> {};

TEST_P(SbvhGpu, AnswersEqualCpuReferenceAndObjectSplitBvh) {
  const Scene scene = test::load_test_scene(GetParam());
  const GpuBvh object = make_gpu_layout(build_bvh(scene), scene);
  const GpuBvh split = make_gpu_layout(build_bvh(scene, test::spatial_splits()), scene);
  const RayBatches b = test::small_ray_batches(scene, object, 48, 2304);
  EXPECT_EQ(count_differences(object, split, b.primary, "primary"), 0);
  EXPECT_EQ(count_differences(object, split, b.ao.rays, "ao"), 0);
  EXPECT_EQ(count_differences(object, split, b.diffuse.rays, "diffuse"), 0);
  EXPECT_EQ(context().validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(StandIns, SbvhGpu, testing::ValuesIn(test::reference_scene_names()),
                         test::scene_param_name);

// The extreme-case suite (tests/extreme_cases.h) over SBVHs: the same answers, and the exact
// rules (no escape from closed meshes, no self-hits) on the device's answers (without the huge
// triangle, as the suite checks them).
class ExtremeRaysSbvh : public testing::TestWithParam<test::Frame> {};

TEST_P(ExtremeRaysSbvh, EqualObjectSplitAnswersAndKeepTheExactRules) {
  for (const bool huge : {false, true}) {
    const test::ExtremeScene x = test::make_extreme_scene(GetParam(), huge);
    const GpuBvh object = make_gpu_layout(build_bvh(x.scene), x.scene);
    const GpuBvh split = make_gpu_layout(build_bvh(x.scene, test::spatial_splits()), x.scene);
    const std::vector<gpu::Ray> rays = test::extreme_rays(x, split.bounds.center());
    EXPECT_EQ(count_differences(object, split, rays, GetParam().name), 0) << huge;
    GpuTracer tracer(context(), split);
    EXPECT_EQ(test::count_extreme_failures(x, tracer.trace(rays, QueryKind::kClosest).hits), 0)
        << huge;
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Frames, ExtremeRaysSbvh, testing::ValuesIn(test::extreme_frames()),
                         test::frame_param_name<testing::TestParamInfo<test::Frame>>);

// The leak suite (tests/extreme_cases.h) over SBVHs: the object-split BVH's answers, and no ray
// from inside a closed mesh escapes it (cut references must leave no gap between leaf boxes).
class LeakRaysSbvh : public testing::TestWithParam<test::LeakFrame> {};

TEST_P(LeakRaysSbvh, EqualObjectSplitAnswersAndNothingEscapes) {
  const test::LeakScene x = test::make_leak_scene(GetParam());
  const GpuBvh object = make_gpu_layout(build_bvh(x.scene), x.scene);
  const Bvh sbvh = build_bvh(x.scene, test::spatial_splits());
  EXPECT_GT(sbvh.prim_ids.size(), x.scene.triangles.size());  // some triangles were cut
  const GpuBvh split = make_gpu_layout(sbvh, x.scene);
  const std::vector<gpu::Ray> rays = test::group_rays(x.groups);
  EXPECT_EQ(count_differences(object, split, rays, GetParam().name), 0);
  GpuTracer tracer(context(), split);
  EXPECT_EQ(test::count_rule_breaks(x.groups, tracer.trace(rays, QueryKind::kClosest).hits), 0)
      << GetParam().name;  // escapes: the leak suite's groups hit their own mesh
  EXPECT_EQ(context().validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Frames, LeakRaysSbvh, testing::ValuesIn(test::leak_frames()),
                         test::frame_param_name<testing::TestParamInfo<test::LeakFrame>>);

// HRPP over an SBVH of the bunny scene (triangles in several leaves predict from the first):
// exact answers equal HRPP off, and in the deterministic configuration the CPU reference
// predictor reproduces the GPU's hits and counters (speculative and exact, go-up 0 and 2).
TEST(SbvhHrpp, ReferencePredictorAgreesAndExactEqualsOff) {
  const Scene scene = test::load_test_scene("bunny.scene.json");
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene, test::spatial_splits()), scene);
  const RayBatches b = test::small_ray_batches(scene, bvh, 32, 1024);
  std::vector<gpu::Ray> primary = b.primary;
  primary.insert(primary.end(), b.primary.begin(), b.primary.end());  // the second finds it warm
  GpuTracerConfig tc;
  tc.rays_per_invocation = 8;
  GpuTracer off(context(), bvh, tc);
  for (const PredictorMode mode : {PredictorMode::kSpeculative, PredictorMode::kExact})
    for (const std::uint32_t go_up : {0u, 2u})
      for (const QueryKind kind : kQueryKinds) {
        const bool any = kind == QueryKind::kAny;
        if (any && mode == PredictorMode::kExact) continue;  // hit-any has one mode
        const std::vector<gpu::Ray>& rays = any ? b.ao.rays : primary;
        PredictorConfig p;
        p.enabled = true;
        p.mode = mode;
        p.set_table({1u << 12, 8, 16, TablePolicy::kNone});
        p.set_hash({HashKind::kIeee, any ? 3u : 6u});
        p.set_go_up(go_up);
        p.batch = 64;
        p.serial = true;
        p.count_baseline = true;
        const std::string what = std::string(predictor_mode_name(mode)) + " go-up " +
                                 std::to_string(go_up) + (any ? " any" : " closest");
        const auto tracer = make_device_tracer(context(), DeviceTracerKind::kCompute, bvh, tc, p);
        const GpuTraceResult gpu = tracer->trace(rays, kind);
        ReferencePredictor cpu_predictor(bvh, p);
        const PredictorTraceResult cpu = cpu_predictor.trace(rays, ray_file_class(kind));
        int differ = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) differ += !test::same_hit(gpu.hits[i], cpu.hits[i]);
        EXPECT_EQ(differ, 0) << what;
        for (int k = 0; k < HRPP_PC_COUNT; ++k)
          EXPECT_EQ(gpu.predictor.c[k], cpu.predictor.c[k]) << what << " counter " << k;
        EXPECT_GT(gpu.predictor.c[HRPP_PC_TRUE_POSITIVES], 0u) << what;
        if (mode == PredictorMode::kExact || any) {
          const GpuTraceResult reference = off.trace(rays, kind);
          int wrong = 0;
          for (std::size_t i = 0; i < rays.size(); ++i)
            wrong += any ? (gpu.hits[i].prim >= 0) != (reference.hits[i].prim >= 0)
                         : !test::same_hit(gpu.hits[i], reference.hits[i]);
          EXPECT_EQ(wrong, 0) << what;
        }
      }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// `hrpp bench` with --bvh-splits spatial and exact HRPP: every tracer checked against the CPU
// reference (bench exits 1 on a mismatch); a bad value names the flag.
class SbvhCli : public test::CliTest {};

TEST_F(SbvhCli, BenchTracesAnSbvhAndBadValuesNameTheFlag) {
  const test::CliResult r = run("bench teapot --rays 2048 --no-embree --repeat 1 "
                                "--check-rays 2048 --bvh-splits spatial --hrpp on --hrpp-mode exact");
  EXPECT_EQ(r.status, 0) << r.err;
  const test::CliResult bad = run("scene teapot --bvh-splits maybe");
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.err.find("--bvh-splits"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace hrpp
