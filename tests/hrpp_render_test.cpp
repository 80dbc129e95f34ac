// HRPP in `hrpp render` (host/render/ + the trace_*_hrpp kernels), on lavapipe: with exact
// hit-all and hit-any prediction the image equals HRPP off bit for bit (same seed), with a roomy
// table and with tables that evict or drop; speculative prediction under a loose hash changes
// pixels and counts its wrong closest hits; per-class counters add up over a whole render; the
// batched (deterministic-order) mode, whose shadow traces are not dispatched indirectly, too;
// the adaptive predictor's sample frames render HRPP off's image; every shadow key (and go-up
// level) renders HRPP off's image.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "vk/vulkan_context.h"
#include "gpu_test_context.h"
#include "hrpp_counter_checks.h"
#include "render/wavefront_renderer.h"
#include "scene/load_scene.h"

namespace hrpp {
namespace {

using test::context;

const Scene& cornell() {
  static const Scene* s = new Scene(load_scene("builtin:cornell"));
  return *s;
}

RenderResult render(const PredictorConfig& predictor, std::uint32_t spp = 4) {
  static const GpuBvh bvh = make_gpu_layout(build_bvh(cornell(), BvhConfig{}), cornell());
  RenderConfig c;
  c.width = c.height = 48;
  c.spp = spp;
  c.seed = 7;
  c.predictor = predictor;
  WavefrontRenderer renderer(context(), cornell(), bvh, c);
  return renderer.render();
}

PredictorConfig on(PredictorMode mode, const TableConfig& table, std::uint32_t bits) {
  PredictorConfig p;
  p.enabled = true;
  p.mode = mode;
  p.set_table(table);
  p.set_hash({HashKind::kIeee, bits});
  p.count_baseline = true;
  p.adaptive = false;  // every class probes every frame
  return p;
}

void expect_counters_add_up(const RayClassStats& s, const std::string& what) {
  test::expect_predictor_counters_add_up(s.predictor, what);
  EXPECT_LE(s.predictor.c[HRPP_PC_PROBES], s.counters.rays) << what;
}

TEST(HrppRender, ExactPredictionRendersTheImageOfHrppOff) {
  const RenderResult off = render({});
  for (const TableConfig& t :
       {table_preset("small"), table_preset("tiny"), TableConfig{4, 2, 2, TablePolicy::kNone}}) {
    const std::string what = std::to_string(t.sets) + "x" + std::to_string(t.ways) + "x" +
                             std::to_string(t.nodes) + " " + table_policy_name(t.policy);
    const RenderResult exact = render(on(PredictorMode::kExact, t, 4));
    ASSERT_EQ(exact.rgb.size(), off.rgb.size());
    EXPECT_TRUE(exact.rgb == off.rgb) << what;
    EXPECT_EQ(exact.stats.closest().counters.hits, off.stats.closest().counters.hits) << what;
    EXPECT_EQ(exact.stats.shadow().counters.hits, off.stats.shadow().counters.hits) << what;
    expect_counters_add_up(exact.stats.closest(), what + " hit-all");
    expect_counters_add_up(exact.stats.shadow(), what + " hit-any");
    EXPECT_GT(exact.stats.closest().predictor.c[HRPP_PC_TRUE_POSITIVES], 0u) << what;
    // Hit-any true positives on the roomy table: the 8-entry ones (evictions, drops) meet the
    // box's few occluded shadow rays (~10%) by chance, 0 to 2 times at this size.
    if (t.sets > 4) {
      EXPECT_GT(exact.stats.shadow().predictor.c[HRPP_PC_TRUE_POSITIVES], 0u) << what;
    }
    EXPECT_EQ(exact.stats.closest().predictor.c[HRPP_PC_WRONG_CLOSEST], 0u) << what;
    if (t.sets == 4) {
      const int full = t.policy == TablePolicy::kNone ? HRPP_PC_INSERT_DROPS : HRPP_PC_EVICTIONS;
      EXPECT_GT(exact.stats.closest().predictor.c[full], 0u) << what;
    }
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// Shadow rays are hit-any: whatever key and go-up level their table uses (the light-space keys
// included), predicting them renders HRPP off's image bit for bit.
TEST(HrppRender, EveryShadowKeyRendersTheImageOfHrppOff) {
  const RenderResult off = render({}, 2);
  for (const Named<HashKind>& kind : kHashKindNames)
    for (const std::uint32_t go_up : {0u, 3u}) {
      PredictorConfig p = on(PredictorMode::kSpeculative, table_preset("tuned"), 4);
      p.classes = {{false, false, true}};
      p.hash[RayClass::kShadow] = {kind.value, 4};
      p.go_up[RayClass::kShadow] = go_up;
      const std::string what = std::string(kind.name) + " go-up " + std::to_string(go_up);
      const RenderResult r = render(p, 2);
      EXPECT_TRUE(r.rgb == off.rgb) << what;
      expect_counters_add_up(r.stats.shadow(), what);
      EXPECT_GT(r.stats.shadow().predictor.c[HRPP_PC_PREDICTOR_HITS], 0u) << what;
    }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// The adaptive predictor starts every class with a sample frame: the stage over a sample of
// each trace (shadow and bounce traces dispatched indirectly), then the plain trace over every
// ray. Speculative prediction under a loose hash, yet the sample frames' image is HRPP off's.
TEST(HrppRender, SampleFramesRenderTheImageOfHrppOff) {
  PredictorConfig p = on(PredictorMode::kSpeculative, table_preset("small"), 3);
  p.adaptive = true;
  p.count_baseline = false;
  p.sample = 2;  // 48x48: every other block of 256 rays
  const RenderResult off = render({}, 1);
  const RenderResult sampled = render(p, 1);
  EXPECT_TRUE(sampled.rgb == off.rgb);
  ASSERT_EQ(sampled.stats.frames.size(), 1u);
  const FrameStats& f = sampled.stats.frames[0];
  for (RayClass k : kRayClasses) {
    const std::string what = ray_class_name(k);
    EXPECT_EQ(f.decisions[k].mode, Probe::kSample) << what;
    EXPECT_GT(f.classes[k].sampled, 0u) << what;
    EXPECT_LT(f.classes[k].sampled, f.classes[k].counters.rays) << what;
    EXPECT_LE(f.classes[k].predictor.c[HRPP_PC_PROBES], f.classes[k].sampled) << what;
    EXPECT_EQ(f.classes[k].traced, f.classes[k].counters.rays) << what;  // every ray, plainly
    EXPECT_GT(f.classes[k].kernels_ms.count(TimerLabel{Kernel::hrpp_predict, Phase::kSample}), 0u)
        << what;
    // The empty dispatch that measures a dispatch's fixed cost ran and was timed.
    EXPECT_GT(f.classes[k].kernels_ms.count(TimerLabel{Kernel::hrpp_predict, Phase::kSampleEmpty}),
              0u)
        << what;
    EXPECT_GT(f.decisions[k].dispatch_ms, 0.0) << what;
    // (Visit counts vary run to run by a few: a lane's extra steps depend on its subgroup's
    // other rays, and the wavefront's queue order is not fixed.)
    EXPECT_EQ(f.classes[k].counters.rays, off.stats.classes[k].counters.rays) << what;
    EXPECT_EQ(f.classes[k].counters.hits, off.stats.classes[k].counters.hits) << what;
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// The deterministic batched mode needs each trace's ray count on the host, so the renderer
// records a bounce's shadow half in a second submit instead of dispatching it indirectly.
TEST(HrppRender, BatchedModeRendersTheImageOfHrppOff) {
  const RenderResult off = render({});
  PredictorConfig p = on(PredictorMode::kExact, table_preset("small"), 4);
  p.batch = 256;
  const RenderResult batched = render(p);
  EXPECT_TRUE(batched.rgb == off.rgb);
  EXPECT_EQ(batched.stats.shadow().counters.rays, off.stats.shadow().counters.rays);
  EXPECT_EQ(batched.stats.shadow().traces, off.stats.shadow().traces);
  EXPECT_GT(batched.stats.shadow().predictor.c[HRPP_PC_TRUE_POSITIVES], 0u);
  expect_counters_add_up(batched.stats.closest(), "batched hit-all");
  expect_counters_add_up(batched.stats.shadow(), "batched hit-any");
  EXPECT_EQ(context().validation_messages(), 0u);
}

TEST(HrppRender, SpeculativeWrongClosestHitsAreCounted) {
  const RenderResult off = render({});
  const RenderResult spec = render(on(PredictorMode::kSpeculative, table_preset("small"), 2));
  const auto& c = spec.stats.closest().predictor.c;
  EXPECT_GT(c[HRPP_PC_WRONG_CLOSEST], 0u);
  EXPECT_LE(c[HRPP_PC_WRONG_CLOSEST], c[HRPP_PC_TRUE_POSITIVES]);
  EXPECT_FALSE(spec.rgb == off.rgb);  // wrong closest hits change paths
  expect_counters_add_up(spec.stats.closest(), "speculative hit-all");
  std::printf("speculative N=2: %llu wrong closest hits of %llu true positives\n",
              static_cast<unsigned long long>(c[HRPP_PC_WRONG_CLOSEST]),
              static_cast<unsigned long long>(c[HRPP_PC_TRUE_POSITIVES]));
}

}  // namespace
}  // namespace hrpp
