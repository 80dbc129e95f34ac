// HRPP inline in the CPU traversal (host/hrpp/inline_predictor.h) against the CPU reference
// predictor, whose code it runs with the work counters compiled out, and against HRPP off (the
// CPU reference traversal, itself checked against Embree in embree_test): on one thread its
// hits and predictor counters are the reference predictor's; on several, exact and any-hit
// answers stay HRPP off's whichever thread's tables a chunk meets.
#include <atomic>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "cpu_render/cpu_renderer.h"
#include "hrpp/inline_predictor.h"
#include "hrpp/reference_predictor.h"
#include "hrpp_counter_checks.h"
#include "test_scenes.h"
#include "trace/cpu_traversal.h"
#include "trace/ray_batches.h"

namespace hrpp {
namespace {

struct Fixture {
  Scene scene;
  GpuBvh bvh;
  RayBatches batches;
};

// The bunny on a floor with a light, 128×128 primary rays (more than one 4096-ray chunk per
// thread) and as many AO and diffuse rays.
const Fixture& bunny() {
  static const Fixture* f = [] {
    auto* x = new Fixture;
    x->scene = test::load_test_scene("bunny.scene.json");
    const Scene& scene = x->scene;
    x->bvh = make_gpu_layout(build_bvh(scene, {}), scene);
    RayBatchConfig c;
    c.width = c.height = 128;
    c.secondary_count = 128 * 128;
    c.threads = 1;
    x->batches = make_ray_batches(scene, x->bvh, c);
    return x;
  }();
  return *f;
}

PredictorConfig config(PredictorMode mode) {
  PredictorConfig p;
  p.enabled = true;
  p.mode = mode;
  p.set_table({1u << 12, 8, 4, TablePolicy::kLru});
  p.set_hash({HashKind::kIeee, 4});  // coarse: many true positives at 128×128
  return p;
}

struct Case {
  const char* name;
  const std::vector<gpu::Ray>& rays;
  RayClass cls;
};

std::vector<Case> cases() {
  const RayBatches& b = bunny().batches;
  return {{"primary", b.primary, RayClass::kCamera},
          {"ao", b.ao.rays, RayClass::kShadow},
          {"diffuse", b.diffuse.rays, RayClass::kCamera}};
}

int differing_hits(const std::vector<gpu::Hit>& a, const std::vector<gpu::Hit>& b) {
  int diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    diff += a[i].prim != b[i].prim || a[i].t != b[i].t || a[i].u != b[i].u || a[i].v != b[i].v;
  return diff;
}

TEST(InlinePredictor, OneThreadIsTheReferencePredictor) {
  for (const TableSharing sharing : {TableSharing::kPerThread, TableSharing::kShared})
  for (const PredictorMode mode : {PredictorMode::kSpeculative, PredictorMode::kExact})
    for (const Case& c : cases()) {
      const std::string what = std::string(c.name) + " " + predictor_mode_name(mode) + " " +
                               name_in(kTableSharingNames, sharing);
      ReferencePredictor reference(bunny().bvh, config(mode));
      const PredictorTraceResult ref = reference.trace(c.rays, c.cls);
      InlinePredictor inline_predictor(bunny().bvh, config(mode), 1, sharing);
      std::vector<gpu::Hit> hits(c.rays.size());
      const PredictorTraceResult in = inline_predictor.trace(c.rays, c.cls, hits);
      EXPECT_EQ(differing_hits(hits, ref.hits), 0) << what;
      for (int k = 0; k < HRPP_PC_COUNT; ++k) {
        const bool work = k == HRPP_PC_VERIFY_INTERIOR || k == HRPP_PC_VERIFY_LEAVES ||
                          k == HRPP_PC_VERIFY_TRIANGLES;
        EXPECT_EQ(in.predictor.c[k], work ? 0u : ref.predictor.c[k]) << what << " counter " << k;
      }
      EXPECT_EQ(in.counters.rays, ref.counters.rays) << what;
      EXPECT_EQ(in.counters.hits, ref.counters.hits) << what;
      EXPECT_EQ(in.counters.interior_visited, 0u) << what << ": work is not counted";
      EXPECT_GT(ref.predictor.c[HRPP_PC_TRUE_POSITIVES], 0u) << what;
    }
}

TEST(InlinePredictor, ExactAndAnyHitAnswersAreHrppOffsOnEveryThreadCount) {
  for (const TableSharing sharing : {TableSharing::kPerThread, TableSharing::kShared})
  for (const Case& c : cases()) {
    const QueryKind kind = query_kind(c.cls);
    const std::vector<gpu::Hit> off = trace_batch_cpu(bunny().bvh, c.rays, kind, 1);
    for (const int threads : {2, 3}) {
      const std::string what = std::string(c.name) + ", " + std::to_string(threads) +
                               " threads, " + name_in(kTableSharingNames, sharing);
      InlinePredictor p(bunny().bvh, config(PredictorMode::kExact), threads, sharing);
      std::vector<gpu::Hit> hits(c.rays.size());
      const PredictorTraceResult r = p.trace(c.rays, c.cls, hits);
      EXPECT_EQ(differing_hits(hits, off), 0) << what;
      EXPECT_EQ(r.predictor.c[HRPP_PC_PROBES], c.rays.size()) << what;
      test::expect_predictor_counters_add_up(r.predictor, what);
      EXPECT_GT(r.predictor.c[HRPP_PC_TRUE_POSITIVES], 0u) << what;
      std::printf("%-34s probes %llu, true positives %llu\n", what.c_str(),
                  static_cast<unsigned long long>(r.predictor.c[HRPP_PC_PROBES]),
                  static_cast<unsigned long long>(r.predictor.c[HRPP_PC_TRUE_POSITIVES]));
      p.clear();
      std::vector<gpu::Hit> again(c.rays.size());
      EXPECT_EQ(p.trace(c.rays, c.cls, again).predictor.c[HRPP_PC_PROBES], c.rays.size());
      EXPECT_EQ(differing_hits(again, off), 0) << what << ", after clear()";
    }
  }
}

// An outside full trace (HRPP in front of Embree in `hrpp bench`; here the CPU traversal behind
// a counter): any-hit rays a verified prediction answered never call it, the others call it
// once, and the answers stay HRPP off's.
TEST(InlinePredictor, AnOutsideTracerIsCalledOnlyForRaysThePredictionDidNotAnswer) {
  const std::vector<gpu::Ray>& rays = bunny().batches.ao.rays;
  const std::vector<gpu::Hit> off = trace_batch_cpu(bunny().bvh, rays, QueryKind::kAny, 1);
  std::atomic<std::uint64_t> calls{0};
  InlinePredictor p(bunny().bvh, config(PredictorMode::kExact), 2);
  p.set_full_trace([&](const gpu::Ray& r) {
    ++calls;
    return trace_closest(bunny().bvh, r);
  });
  std::vector<gpu::Hit> hits(rays.size());
  const PredictorTraceResult r = p.trace(rays, RayClass::kShadow, hits);
  EXPECT_EQ(differing_hits(hits, off), 0);
  EXPECT_GT(r.predictor.c[HRPP_PC_TRUE_POSITIVES], 0u);
  EXPECT_EQ(calls.load(), rays.size() - r.predictor.c[HRPP_PC_TRUE_POSITIVES]);
}

// The CPU renderer with HRPP inline (exact mode: hit-all answers bounded by the prediction, and
// hit-any answers, are HRPP off's) renders HRPP off's image bit for bit, every class probing.
TEST(InlinePredictor, ExactPredictionInTheCpuRendererKeepsTheImage) {
  RenderConfig config;
  config.width = config.height = 48;
  config.spp = 2;
  config.seed = 5;
  const RenderResult off = CpuRenderer(bunny().scene, bunny().bvh, config).render();
  config.predictor = PredictorConfig{};
  config.predictor.enabled = true;
  config.predictor.mode = PredictorMode::kExact;
  const RenderResult on = CpuRenderer(bunny().scene, bunny().bvh, config).render();
  ASSERT_EQ(on.rgb.size(), off.rgb.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < on.rgb.size(); ++i) differ += on.rgb[i] != off.rgb[i];
  EXPECT_EQ(differ, 0u);
  for (const RayClass c : kRayClasses) {
    const gpu::PredictorCounters& p = on.stats.classes[c].predictor;
    EXPECT_EQ(p.c[HRPP_PC_PROBES], on.stats.classes[c].counters.rays) << ray_class_name(c);
    test::expect_predictor_counters_add_up(p, ray_class_name(c));
    EXPECT_EQ(off.stats.classes[c].predictor.c[HRPP_PC_PROBES], 0u) << ray_class_name(c);
  }
  EXPECT_GT(on.stats.classes[RayClass::kCamera].predictor.c[HRPP_PC_TRUE_POSITIVES], 0u);
}

}  // namespace
}  // namespace hrpp
