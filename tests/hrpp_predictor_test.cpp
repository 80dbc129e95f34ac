// HRPP on the GPU (host/front/gpu_predictor, shaders/lib/hrpp_*.glsl) against HRPP off and the CPU
// reference predictor (host/hrpp/reference_predictor), on lavapipe:
//   - exact hit-all and hit-any answers equal HRPP off ray for ray, with a roomy table, a tiny
//     LRU table (evictions counted) and a tiny table that drops;
//   - counters add up (TP + FP = predictor hits, hits + negatives = probes, requests = inserts +
//     present + drops) and the table holds what was inserted;
//   - in the deterministic configuration (batches with deferred inserts, one ray per subgroup,
//     a table that neither evicts nor drops) the CPU reference reproduces every GPU counter and
//     every hit, for speculative / exact hit-all and hit-any, go-up 0 and 2;
//   - speculative hit-all's wrong closest hits are counted, and equal the ones found by
//     comparing with HRPP off;
//   - shadow rays towards the scene's area light under every hash kind (the light-space keys
//     included) and go-up 0 and 3: answers equal HRPP off, and the CPU reference reproduces
//     every counter in the deterministic configuration.
#include <cstdio>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "common/error.h"
#include "front/make_device_tracer.h"
#include "front/gpu_predictor.h"
#include "gpu/gpu_tracer.h"
#include "vk/vulkan_context.h"
#include "gpu_test_context.h"
#include "hrpp/reference_predictor.h"
#include "hrpp/reference_table.h"
#include "hrpp_distance_gate.h"
#include "hrpp_table_set.h"
#include "hrpp_counter_checks.h"
#include "test_scenes.h"
#include "trace/ray_batches.h"

namespace hrpp {
namespace {

using test::context;

struct Fixture {
  Scene scene;
  GpuBvh bvh;
  std::vector<gpu::Ray> primary, ao, diffuse;
  std::vector<gpu::Ray> light;  // shadow rays from the primaries' hits to the area light
};

// Two shadow rays per primary hit, each to a uniform point of the bunny scene's light (the quad
// y = 2.5, x and z in [-0.5, 0.5]), offset off the surface by backing up the primary ray and
// ending just short of the light (as the renderer's shadow rays do).
std::vector<gpu::Ray> light_rays(const RayBatches& b) {
  std::vector<gpu::Ray> rays;
  std::uint32_t state = 12345u;
  const auto u = [&state] {
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) / 16777216.0f;
  };
  for (std::size_t i = 0; i < b.primary.size(); ++i) {
    const gpu::Hit& h = b.primary_hits[i];
    if (h.prim < 0) continue;
    const glm::vec3 p = b.primary[i].origin + (h.t * 0.9999f) * b.primary[i].dir;
    for (int k = 0; k < 2; ++k) {
      const glm::vec3 q{u() - 0.5f, 2.5f, u() - 0.5f};
      const float len = glm::length(q - p);
      rays.push_back({p, 0.0f, (q - p) / len, len * 0.9999f});
    }
  }
  return rays;
}

// The bunny scene at 48×48 (primaries twice: the second pass finds the table warm), 2048 AO and
// diffuse rays.
const Fixture& bunny() {
  static const Fixture* f = [] {
    auto* x = new Fixture;
    x->scene = test::load_test_scene("bunny.scene.json");  // the bunny on a floor, a light
    x->bvh = make_gpu_layout(build_bvh(x->scene, {}), x->scene);
    RayBatchConfig c;
    c.width = c.height = 48;
    c.secondary_count = 2048;
    c.threads = 1;
    const RayBatches b = make_ray_batches(x->scene, x->bvh, c);
    x->primary = b.primary;
    x->primary.insert(x->primary.end(), b.primary.begin(), b.primary.end());
    x->ao = b.ao.rays;
    x->diffuse = b.diffuse.rays;
    x->light = light_rays(b);
    return x;
  }();
  return *f;
}

PredictorConfig config(PredictorMode mode, TableConfig table) {
  PredictorConfig p;
  p.enabled = true;
  p.mode = mode;
  p.set_table(table);
  p.set_hash({HashKind::kIeee, 6});
  return p;
}

GpuTraceResult trace_gpu(const PredictorConfig& p, const std::vector<gpu::Ray>& rays,
                         QueryKind kind, DeviceTracer** keep = nullptr) {
  GpuTracerConfig tc;
  tc.rays_per_invocation = 8;
  // Never destroyed, like the context they use (gpu_test_context.h): at exit the driver may
  // already be torn down (Debian 13's build crashed destroying them there).
  static auto* tracers = new std::vector<std::unique_ptr<DeviceTracer>>;
  tracers->push_back(make_device_tracer(context(), DeviceTracerKind::kCompute, bunny().bvh, tc, p));
  if (keep) *keep = tracers->back().get();
  return tracers->back()->trace(rays, kind);
}

void expect_counters_add_up(const gpu::PredictorCounters& pc, std::size_t valid_rays,
                            const std::string& what) {
  EXPECT_EQ(pc.c[HRPP_PC_PROBES], valid_rays) << what;
  test::expect_predictor_counters_add_up(pc, what);
}

void expect_same_hits(const std::vector<gpu::Hit>& a, const std::vector<gpu::Hit>& b,
                      const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  int diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].prim != b[i].prim || a[i].t != b[i].t || a[i].u != b[i].u || a[i].v != b[i].v) {
      if (++diff <= 3)
        ADD_FAILURE() << what << ": ray " << i << " prim " << a[i].prim << " t " << a[i].t
                      << " vs prim " << b[i].prim << " t " << b[i].t;
    }
  EXPECT_EQ(diff, 0) << what;
}

// Hash precision per ray kind: a few thousand secondary rays only meet similar rays under a
// coarse hash (the paper's precision 6 is for a million rays per frame).
struct Case {
  const char* name;
  const std::vector<gpu::Ray>* rays;
  QueryKind kind;
  std::uint32_t bits;
};

std::vector<Case> cases() {
  return {{"primary", &bunny().primary, QueryKind::kClosest, 6},
          {"diffuse", &bunny().diffuse, QueryKind::kClosest, 3},
          {"ao", &bunny().ao, QueryKind::kAny, 3}};
}

// Exact and any-hit prediction never change an answer, however small the table.
TEST(HrppPredictor, ExactAndAnyHitEqualHrppOff) {
  GpuTracerConfig off_config;
  off_config.rays_per_invocation = 8;
  GpuTracer off(context(), bunny().bvh, off_config);
  const TableConfig tables[] = {table_preset("small"), table_preset("tiny"),
                                {4, 2, 2, TablePolicy::kNone}};
  for (const Case& c : cases()) {
    const GpuTraceResult reference = off.trace(*c.rays, c.kind);
    for (const TableConfig& t : tables) {
      const std::string what = std::string(c.name) + " table " + std::to_string(t.sets) + "x" +
                               std::to_string(t.ways) + "x" + std::to_string(t.nodes) + " " +
                               table_policy_name(t.policy);
      DeviceTracer* tracer = nullptr;
      PredictorConfig p = config(PredictorMode::kExact, t);
      p.set_hash({HashKind::kIeee, c.bits});
      trace_gpu(p, *c.rays, c.kind, &tracer);  // a trace's inserts serve the next traces
      const GpuTraceResult on = tracer->trace(*c.rays, c.kind);
      expect_same_hits(on.hits, reference.hits, what);
      expect_counters_add_up(on.predictor, c.rays->size(), what);
      const auto& pc = on.predictor.c;
      const TableOccupancy occ = tracer->predictor()->occupancy(ray_file_class(c.kind));
      EXPECT_GT(occ.entries, 0u) << what;
      EXPECT_LE(occ.entries, occ.capacity) << what;
      EXPECT_LE(occ.nodes, occ.entries * t.nodes) << what;
      if (t.sets == 4) {  // 8 entries of 2 nodes: full at once
        EXPECT_EQ(occ.entries, occ.capacity) << what;
        if (t.policy != TablePolicy::kNone) {
          EXPECT_GT(pc[HRPP_PC_EVICTIONS], 0u) << what;
        } else {
          EXPECT_GT(pc[HRPP_PC_INSERT_DROPS], 0u) << what;
          EXPECT_EQ(pc[HRPP_PC_EVICTIONS], 0u) << what;
        }
      } else {
        EXPECT_GT(pc[HRPP_PC_TRUE_POSITIVES], 0u) << what;
        // Nothing evicted or dropped: every inserted node is in the table.
        EXPECT_EQ(pc[HRPP_PC_EVICTIONS] + pc[HRPP_PC_INSERT_DROPS], 0u) << what;
        EXPECT_GE(occ.nodes, pc[HRPP_PC_INSERTS]) << what;  // + the first trace's
      }
    }
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// MICRO'21's predictor as published (its key at 5 grid bits, its table) in exact mode, and on
// the AO rays it was built for: every answer is HRPP off's, and it predicts.
TEST(HrppPredictor, Micro21ExactAndAnyHitEqualHrppOff) {
  GpuTracerConfig off_config;
  off_config.rays_per_invocation = 8;
  GpuTracer off(context(), bunny().bvh, off_config);
  for (const Case& c : cases()) {
    const GpuTraceResult reference = off.trace(*c.rays, c.kind);
    PredictorConfig p = config(PredictorMode::kExact, table_preset("micro21"));
    p.set_hash({HashKind::kMicro21, 5});
    const std::string what = std::string("micro21 ") + c.name;
    DeviceTracer* tracer = nullptr;
    trace_gpu(p, *c.rays, c.kind, &tracer);  // a trace's inserts serve the next
    const GpuTraceResult on = tracer->trace(*c.rays, c.kind);
    expect_same_hits(on.hits, reference.hits, what);
    expect_counters_add_up(on.predictor, c.rays->size(), what);
    EXPECT_GT(on.predictor.c[HRPP_PC_TRUE_POSITIVES], 0u) << what;
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// One deterministic trace (batches of 64, one ray per subgroup) on the GPU and on the CPU
// reference predictor: the same hits, counters and table contents. The key: `hash`, else the
// case's IEEE precision.
void expect_reference_reproduces_gpu(const PredictorConfig& config, const Case& c,
                                     const HashConfig* hash = nullptr) {
  PredictorConfig p = config;
  p.set_hash(hash ? *hash : HashConfig{HashKind::kIeee, c.bits});
  p.batch = 64;
  p.serial = true;
  p.count_baseline = true;
  const TableConfig& table = p.table[RayClass::kCamera];
  const std::string what = std::string(c.name) + " " + predictor_mode_name(p.mode) + " " +
                           hash_kind_name(p.hash[RayClass::kCamera].kind) +
                           (p.gate[RayClass::kCamera] > 0.0f ? " gated" : "") + " " +
                           fallback_name(p.fallback) + " go-up " +
                           std::to_string(p.go_up[RayClass::kCamera]) + " table " +
                           std::to_string(table.sets) + "x" + std::to_string(table.ways) + "x" +
                           std::to_string(table.nodes) + " " + table_policy_name(table.policy);
  DeviceTracer* tracer = nullptr;
  const GpuTraceResult gpu = trace_gpu(p, *c.rays, c.kind, &tracer);
  ReferencePredictor cpu_predictor(bunny().bvh, p);
  const PredictorTraceResult cpu = cpu_predictor.trace(*c.rays, ray_file_class(c.kind));
  expect_same_hits(gpu.hits, cpu.hits, what);
  for (int k = 0; k < HRPP_PC_COUNT; ++k)
    EXPECT_EQ(gpu.predictor.c[k], cpu.predictor.c[k]) << what << " counter " << k;
  EXPECT_EQ(gpu.counters.interior_visited, cpu.counters.interior_visited) << what;
  EXPECT_EQ(gpu.counters.leaves_visited, cpu.counters.leaves_visited) << what;
  EXPECT_EQ(gpu.counters.triangles_tested, cpu.counters.triangles_tested) << what;
  EXPECT_EQ(gpu.counters.hits, cpu.counters.hits) << what;
  const TableOccupancy occ = tracer->predictor()->occupancy(ray_file_class(c.kind));
  EXPECT_EQ(occ.entries, cpu_predictor.entries(ray_file_class(c.kind))) << what;
  EXPECT_EQ(occ.nodes, cpu_predictor.stored_nodes(ray_file_class(c.kind))) << what;
  expect_counters_add_up(gpu.predictor, c.rays->size(), what);
  if (table.sets > 4) {
    EXPECT_GT(cpu.predictor.c[HRPP_PC_TRUE_POSITIVES], 0u) << what;
  } else {  // tiny tables: they evict or drop
    const int full = table.policy == TablePolicy::kNone ? HRPP_PC_INSERT_DROPS : HRPP_PC_EVICTIONS;
    EXPECT_GT(cpu.predictor.c[full], 0u) << what;
  }
  std::printf("%-32s probes %llu TP %llu FP %llu neg %llu wrong %llu gated %llu\n", what.c_str(),
              static_cast<unsigned long long>(gpu.predictor.c[HRPP_PC_PROBES]),
              static_cast<unsigned long long>(gpu.predictor.c[HRPP_PC_TRUE_POSITIVES]),
              static_cast<unsigned long long>(gpu.predictor.c[HRPP_PC_FALSE_POSITIVES]),
              static_cast<unsigned long long>(gpu.predictor.c[HRPP_PC_NEGATIVES]),
              static_cast<unsigned long long>(gpu.predictor.c[HRPP_PC_WRONG_CLOSEST]),
              static_cast<unsigned long long>(gpu.predictor.c[HRPP_PC_GATED]));
}

// The deterministic configuration reproduced: a roomy table and tiny ones that evict (lru,
// fifo, micro21) or drop (none), leaves and go-up 2 (the roomy table), with either fallback
// (root: go-up 2); MICRO'21's predictor as published (its key and table).
TEST(HrppPredictor, ReferencePredictorReproducesGpuCounters) {
  const TableConfig roomy{1u << 12, 8, 16, TablePolicy::kNone};
  const TableConfig tiny[] = {{4, 2, 2, TablePolicy::kLru},
                              {4, 2, 2, TablePolicy::kFifo},
                              {4, 2, 2, TablePolicy::kNone},
                              {4, 1, 2, TablePolicy::kMicro21}};
  const HashConfig micro21{HashKind::kMicro21, 5};
  for (const PredictorMode mode : {PredictorMode::kSpeculative, PredictorMode::kExact})
    for (const Case& c : cases()) {
      if (c.kind == QueryKind::kAny && mode == PredictorMode::kExact) continue;  // one mode
      for (const TableConfig& table : tiny) expect_reference_reproduces_gpu(config(mode, table), c);
      expect_reference_reproduces_gpu(config(mode, table_preset("micro21")), c, &micro21);
      PredictorConfig p = config(mode, roomy);
      expect_reference_reproduces_gpu(p, c);
      p.set_go_up(2);
      for (const Fallback fallback : {Fallback::kSkip, Fallback::kRoot}) {
        p.fallback = fallback;
        expect_reference_reproduces_gpu(p, c);
      }
      if (mode == PredictorMode::kSpeculative && c.kind == QueryKind::kClosest)
        for (const TableConfig& table : {roomy, tiny[0]}) {  // the distance gate, lru evicting
          PredictorConfig g = config(mode, table);
          g.gate = {{1.5f, 1.5f, 0.0f}};
          expect_reference_reproduces_gpu(g, c);
        }
    }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// --hrpp-fallback skip: a queued ray's trace does not enter the nodes its prediction tested.
// Answers stay HRPP off's, and with the same table (exact closest-hit answers insert the same
// nodes) the trace visits fewer interior nodes than with root, at most the verification's.
TEST(HrppPredictor, SkipFallbackKeepsAnswersAndSavesVerifiedNodes) {
  GpuTracerConfig off_config;
  off_config.rays_per_invocation = 8;
  GpuTracer off(context(), bunny().bvh, off_config);
  const Case c = cases()[1];  // diffuse rays, exact: true positives are queued too
  const GpuTraceResult reference = off.trace(*c.rays, c.kind);
  GpuTraceResult runs[2];
  for (const Fallback f : {Fallback::kRoot, Fallback::kSkip}) {
    PredictorConfig p = config(PredictorMode::kExact, {1u << 12, 8, 4, TablePolicy::kNone});
    p.set_go_up(2);
    p.set_hash({HashKind::kIeee, c.bits});
    p.batch = 64;
    p.serial = true;
    p.fallback = f;
    GpuTraceResult& r = runs[f == Fallback::kSkip];
    r = trace_gpu(p, *c.rays, c.kind);
    expect_same_hits(r.hits, reference.hits, fallback_name(f));
  }
  const auto& pc = runs[1].predictor.c;
  EXPECT_GT(pc[HRPP_PC_PREDICTOR_HITS], 100u);
  for (int k = 0; k < HRPP_PC_COUNT; ++k) EXPECT_EQ(pc[k], runs[0].predictor.c[k]) << k;
  const std::uint64_t root = runs[0].counters.interior_visited;
  const std::uint64_t skip = runs[1].counters.interior_visited;
  EXPECT_LT(skip, root);
  EXPECT_LE(root - skip, pc[HRPP_PC_VERIFY_INTERIOR]);
  EXPECT_EQ(context().validation_messages(), 0u);
}

// hrpp_predict's workgroup is one subgroup where that divides the trace kernels' 64 lanes (each
// invocation then takes 64 / subgroup times the trace's rays: the tests here run it at 8 lanes
// on lavapipe), else 64.
TEST(HrppPredictor, PredictWorkgroupIsOneSubgroup) {
  EXPECT_EQ(predict_workgroup_size(8), 8u);
  EXPECT_EQ(predict_workgroup_size(32), 32u);
  EXPECT_EQ(predict_workgroup_size(64), 64u);
  EXPECT_EQ(predict_workgroup_size(1), 1u);
  EXPECT_EQ(predict_workgroup_size(128), 64u);
  EXPECT_EQ(predict_workgroup_size(24), 64u);
  EXPECT_EQ(predict_workgroup_size(0), 64u);
  EXPECT_EQ(predict_workgroup_size(context().info().subgroup_size), context().info().subgroup_size);
}

// Every hash kind keys shadow rays (the light-space keys among them), with leaves and with
// go-up subtrees stored: hit-any answers stay HRPP off's, with inserts during the trace and in
// the deterministic configuration, where the CPU reference reproduces every GPU counter.
TEST(HrppPredictor, ShadowKeysKeepAnswersAndMatchTheReference) {
  GpuTracerConfig off_config;
  off_config.rays_per_invocation = 8;
  GpuTracer off(context(), bunny().bvh, off_config);
  const std::vector<gpu::Ray>& rays = bunny().light;
  ASSERT_GT(rays.size(), 1000u);
  const GpuTraceResult reference = off.trace(rays, QueryKind::kAny);
  std::size_t occluded = 0;
  for (const gpu::Hit& h : reference.hits) occluded += h.prim >= 0;
  ASSERT_GT(occluded, rays.size() / 10);  // the bunny shadows the floor
  for (const Named<HashKind>& kind : kHashKindNames)
    for (const std::uint32_t go_up : {0u, 3u}) {
      PredictorConfig p = config(PredictorMode::kSpeculative, table_preset("tuned"));
      p.hash[RayClass::kShadow] = {kind.value, 4};
      p.go_up[RayClass::kShadow] = go_up;
      const std::string what = std::string(kind.name) + " go-up " + std::to_string(go_up);
      DeviceTracer* tracer = nullptr;
      trace_gpu(p, rays, QueryKind::kAny, &tracer);
      const GpuTraceResult warm = tracer->trace(rays, QueryKind::kAny);
      expect_same_hits(warm.hits, reference.hits, what + " (inserts during the trace)");
      p.set_table({1u << 12, 8, 16, TablePolicy::kNone});
      p.batch = 64;
      p.serial = true;
      p.count_baseline = true;
      const GpuTraceResult gpu = trace_gpu(p, rays, QueryKind::kAny);
      ReferencePredictor cpu_predictor(bunny().bvh, p);
      const PredictorTraceResult cpu = cpu_predictor.trace(rays, RayClass::kShadow);
      expect_same_hits(gpu.hits, reference.hits, what);
      expect_same_hits(cpu.hits, reference.hits, what + " (CPU reference)");
      for (int k = 0; k < HRPP_PC_COUNT; ++k)
        EXPECT_EQ(gpu.predictor.c[k], cpu.predictor.c[k]) << what << " counter " << k;
      EXPECT_EQ(gpu.counters.interior_visited, cpu.counters.interior_visited) << what;
      EXPECT_EQ(gpu.counters.triangles_tested, cpu.counters.triangles_tested) << what;
      expect_counters_add_up(gpu.predictor, rays.size(), what);
      if (is_light_space(kind.value)) {
        EXPECT_GT(gpu.predictor.c[HRPP_PC_TRUE_POSITIVES], 0u) << what;
      }
      std::printf("%-22s %zu rays, %zu occluded: TP %llu FP %llu neg %llu\n", what.c_str(),
                  rays.size(), occluded,
                  static_cast<unsigned long long>(gpu.predictor.c[HRPP_PC_TRUE_POSITIVES]),
                  static_cast<unsigned long long>(gpu.predictor.c[HRPP_PC_FALSE_POSITIVES]),
                  static_cast<unsigned long long>(gpu.predictor.c[HRPP_PC_NEGATIVES]));
    }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// The HRPP stage's queue: every ray is answered once, by its prediction or by the trace of the
// queue, whatever the number of rays (1 ray, part of a subgroup, workgroups of one ray per
// invocation) and however small the table; the trace kernel traces exactly the rays that were
// not answered by a true positive (speculative), and exact answers equal HRPP off.
TEST(HrppPredictor, QueueAnswersEveryRayOnce) {
  GpuTracerConfig tc;
  tc.rays_per_invocation = 1;
  GpuTracer off(context(), bunny().bvh, tc);
  for (const std::size_t n : {std::size_t{1}, std::size_t{7}, std::size_t{65}, std::size_t{1500}})
    for (const PredictorMode mode : {PredictorMode::kSpeculative, PredictorMode::kExact})
      for (const TableConfig& t : {table_preset("tiny"), table_preset("small")}) {
        const std::vector<gpu::Ray> rays(bunny().primary.begin(),
                                         bunny().primary.begin() + static_cast<long>(n));
        const std::string what = std::to_string(n) + " rays " + predictor_mode_name(mode) +
                                 " table " + std::to_string(t.entries());
        PredictorConfig p = config(mode, t);
        p.set_hash({HashKind::kIeee, 4});  // coarse: many predictor hits even among a few rays
        const auto on = make_device_tracer(context(), DeviceTracerKind::kCompute, bunny().bvh, tc, p);
        on->trace(rays, QueryKind::kClosest);  // fills the table
        const GpuTraceResult r = on->trace(rays, QueryKind::kClosest);
        ASSERT_EQ(r.hits.size(), n) << what;
        EXPECT_TRUE(r.predicted) << what;
        EXPECT_EQ(r.counters.rays, n) << what;
        expect_counters_add_up(r.predictor, n, what);
        const std::uint64_t tp = r.predictor.c[HRPP_PC_TRUE_POSITIVES];
        EXPECT_EQ(r.traced, mode == PredictorMode::kExact ? n : n - tp) << what;
        std::uint64_t hits = 0;
        for (const gpu::Hit& h : r.hits) hits += h.prim >= 0;
        EXPECT_EQ(r.counters.hits, hits) << what;
        if (mode == PredictorMode::kExact)
          expect_same_hits(r.hits, off.trace(rays, QueryKind::kClosest).hits, what);
        if (n == 1500 && t.entries() > 8) {
          EXPECT_GT(tp, 0u) << what;
        }
      }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// The adaptive predictor's sample (Probe::kSample): the HRPP stage runs over every
// PredictorConfig::sample-th ray and the plain trace over every ray, so the answers are HRPP
// off's, speculative or not, and the HRPP counters are the sample's.
TEST(HrppPredictor, SampleAnswersAreHrppOffs) {
  GpuTracerConfig tc;
  tc.rays_per_invocation = 1;
  GpuTracer off(context(), bunny().bvh, tc);
  for (const Case& k : cases())
    for (const std::size_t n : {std::size_t{1}, std::size_t{33}, k.rays->size()}) {
      const std::vector<gpu::Ray> rays(k.rays->begin(), k.rays->begin() + static_cast<long>(n));
      const std::string what = std::string(k.name) + " " + std::to_string(n) + " rays";
      PredictorConfig p = config(PredictorMode::kSpeculative, table_preset("small"));
      p.set_hash({HashKind::kIeee, 3});  // coarse: predictor hits, wrong ones among them
      const auto on = make_device_tracer(context(), DeviceTracerKind::kCompute, bunny().bvh, tc, p);
      on->trace(rays, k.kind);  // every ray predicted: fills the table
      on->predictor()->set_probing(ray_file_class(k.kind), Probe::kSample);
      const GpuTraceResult r = on->trace(rays, k.kind);
      const GpuTraceResult plain = off.trace(rays, k.kind);
      EXPECT_FALSE(r.predicted) << what;
      EXPECT_EQ(r.sampled, gpu::hrpp_pass_ray_count(static_cast<std::uint32_t>(n),
                                                    HRPP_PASS_SAMPLE, p.sample))
          << what;
      EXPECT_LT(r.sampled, n > HRPP_SAMPLE_BLOCK ? n : n + 1) << what;
      EXPECT_EQ(r.traced, n) << what;
      EXPECT_EQ(r.counters.interior_visited, plain.counters.interior_visited) << what;
      expect_counters_add_up(r.predictor, r.sampled, what);
      expect_same_hits(r.hits, plain.hits, what);
    }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// Speculative hit-all: the wrong closest hits counted on the GPU are the ones that differ from
// HRPP off.
TEST(HrppPredictor, SpeculativeWrongClosestHitsAreCounted) {
  GpuTracerConfig off_config;
  off_config.rays_per_invocation = 8;
  GpuTracer off(context(), bunny().bvh, off_config);
  for (const Case& c : cases()) {
    if (c.kind == QueryKind::kAny) continue;
    PredictorConfig p = config(PredictorMode::kSpeculative, table_preset("small"));
    p.count_baseline = true;
    p.set_hash({HashKind::kIeee, c.bits - 2});  // loose: more wrong answers to count
    const GpuTraceResult on = trace_gpu(p, *c.rays, QueryKind::kClosest);
    const GpuTraceResult reference = off.trace(*c.rays, QueryKind::kClosest);
    std::uint64_t differ = 0;
    for (std::size_t i = 0; i < c.rays->size(); ++i)
      differ += on.hits[i].prim != reference.hits[i].prim || on.hits[i].t != reference.hits[i].t;
    EXPECT_EQ(on.predictor.c[HRPP_PC_WRONG_CLOSEST], differ) << c.name;
    expect_counters_add_up(on.predictor, c.rays->size(), c.name);
    std::printf("%s speculative N=%u: %llu wrong closest hits of %zu rays\n", c.name,
                p.hash[RayClass::kCamera].bits, static_cast<unsigned long long>(differ),
                c.rays->size());
  }
}

// The distance gate: a gated true positive bounds a full traversal, so with a gate that stops
// every true positive (G tiny) the answers are HRPP off's and nothing is wrong; with G = 1.5 the
// wrong closest hits counted are still exactly the answers that differ from HRPP off's.
TEST(HrppPredictor, DistanceGateBoundsTheTraceOfFarPredictions) {
  GpuTracerConfig off_config;
  off_config.rays_per_invocation = 8;
  GpuTracer off(context(), bunny().bvh, off_config);
  for (const Case& c : cases()) {
    if (c.kind == QueryKind::kAny) continue;
    const GpuTraceResult reference = off.trace(*c.rays, QueryKind::kClosest);
    for (const float gate : {1e-20f, 1.5f}) {
      char what_text[64];
      std::snprintf(what_text, sizeof what_text, "%s gate %g", c.name, static_cast<double>(gate));
      const std::string what = what_text;
      PredictorConfig p = config(PredictorMode::kSpeculative, table_preset("small"));
      p.count_baseline = true;
      p.set_hash({HashKind::kIeee, c.bits - 2});  // loose: wrong answers to stop
      p.gate = {{gate, gate, 0.0f}};
      const GpuTraceResult on = trace_gpu(p, *c.rays, QueryKind::kClosest);
      std::uint64_t differ = 0;
      for (std::size_t i = 0; i < c.rays->size(); ++i)
        differ += on.hits[i].prim != reference.hits[i].prim || on.hits[i].t != reference.hits[i].t;
      const auto& pc = on.predictor.c;
      EXPECT_EQ(pc[HRPP_PC_WRONG_CLOSEST], differ) << what;
      EXPECT_LE(pc[HRPP_PC_GATED], pc[HRPP_PC_TRUE_POSITIVES]) << what;
      if (gate < 1.0f) {
        EXPECT_GT(pc[HRPP_PC_TRUE_POSITIVES], 0u) << what;
        EXPECT_EQ(differ, 0u) << what;
        EXPECT_EQ(pc[HRPP_PC_GATED], pc[HRPP_PC_TRUE_POSITIVES]) << what;
      }
      expect_counters_add_up(on.predictor, c.rays->size(), what);
      std::printf("%s: %llu of %llu true positives gated, %llu wrong closest hits\n", what.c_str(),
                  static_cast<unsigned long long>(pc[HRPP_PC_GATED]),
                  static_cast<unsigned long long>(pc[HRPP_PC_TRUE_POSITIVES]),
                  static_cast<unsigned long long>(differ));
    }
  }
  EXPECT_EQ(context().validation_messages(), 0u);
}

// Which key each policy gives up when a full set takes a new one: one set of two ways, keys 1
// and 2 inserted at clocks 1 and 2, key 1 probed at clock 3, key 3 inserted at clock 4. lru
// evicts key 2 (key 1 was used last), fifo key 1 (it came in first; the probe wrote nothing),
// none drops key 3, micro21 evicts as lru. The GPU table makes the same choices (ReferencePredictorReproducesGpuCounters).
TEST(HrppPredictor, PoliciesEvictTheirVictims) {
  struct Expect {
    TablePolicy policy;
    bool holds[3];  // keys 1, 2, 3 afterwards
    ReferenceTable::Outcome third;
    std::uint64_t evictions;
  };
  using O = ReferenceTable::Outcome;
  for (const Expect& e : {Expect{TablePolicy::kLru, {true, false, true}, O::kInserted, 1},
                          Expect{TablePolicy::kFifo, {false, true, true}, O::kInserted, 1},
                          Expect{TablePolicy::kNone, {true, true, false}, O::kDropped, 0},
                          Expect{TablePolicy::kMicro21, {true, false, true}, O::kInserted, 1}}) {
    gpu::PredictorParams params{};
    params.sets = 1;
    params.ways = 2;
    params.nodes = 2;
    params.policy = static_cast<std::uint32_t>(e.policy);
    ReferenceTable table(params);
    std::uint64_t evictions = 0;
    std::uint32_t nearest = 0;
    EXPECT_EQ(table.insert(1, 10, 1.0f, 1, evictions), O::kInserted);
    EXPECT_EQ(table.insert(2, 20, 1.0f, 2, evictions), O::kInserted);
    ASSERT_FALSE(table.lookup(1, 3, nearest).empty());
    EXPECT_EQ(table.insert(3, 30, 1.0f, 4, evictions), e.third) << table_policy_name(e.policy);
    for (std::uint64_t key = 1; key <= 3; ++key)
      EXPECT_EQ(!table.lookup(key, 5, nearest).empty(), e.holds[key - 1])
          << table_policy_name(e.policy) << " key " << key;
    EXPECT_EQ(evictions, e.evictions) << table_policy_name(e.policy);
  }
}

// MICRO'21's table index (ray-predictor.cc, compute_index) as its source computes it: the hash
// xor-folded in chunks of log2(sets) bits.
std::uint64_t micro21_source_index(std::uint64_t hash, unsigned num_bits) {
  const std::uint64_t mask = UINT64_MAX >> (64 - num_bits);
  std::uint64_t index = 0;
  while (hash > 0) {
    index ^= hash & mask;
    hash >>= num_bits;
  }
  return index;
}

// MICRO'21's table as submitted (its MOBILE configuration: 1024 entries, 4-way set-associative,
// 1 node an entry, LRU; check_table, add_entry and add_node_to_predictor_entry with placement
// 's'), scripted on one SM's table: a key's set is its folded bits (keys 0x004, 0x105, 0x206,
// 0x307 and 0x400 share set 4, which the golden-ratio sets of the other policies would not);
// a probe hit renews its way, so the fifth key evicts the least recently used of the other
// three; a new node replaces an entry's one node.
TEST(HrppPredictor, Micro21TableFoldsKeysAndEvictsTheLeastRecentlyUsed) {
  const TableConfig geometry = table_preset("micro21");
  EXPECT_EQ(geometry, (TableConfig{256, 4, 1, TablePolicy::kMicro21, 2}));  // 2 SMs
  EXPECT_EQ(geometry.bytes(), 2u * 1024u * (8 + 4 + 4));                    // 16 KiB each
  std::mt19937_64 rng(21);
  for (int i = 0; i < 1000; ++i) {
    const std::uint64_t key = rng() >> (64 - HRPP_KEY_BITS + (i % 40));
    for (unsigned bits : {1u, 3u, 8u, 10u})
      ASSERT_EQ(gpu::hrpp_folded_set(key, 1u << bits), micro21_source_index(key, bits)) << key;
    EXPECT_EQ(gpu::hrpp_folded_set(key | (std::uint64_t{1} << HRPP_KEY_BITS), 256),
              gpu::hrpp_folded_set(key, 256));  // an SM table's bits are not folded
  }
  EXPECT_EQ(gpu::hrpp_folded_set(0x7ABC, 256), 0xBCu ^ 0x7Au);
  EXPECT_EQ(gpu::hrpp_folded_set(0x7ABC, 1), 0u);
  gpu::PredictorParams params{};  // one SM's table
  params.sets = geometry.sets;
  params.ways = geometry.ways;
  params.nodes = geometry.nodes;
  params.policy = static_cast<std::uint32_t>(geometry.policy);
  ReferenceTable table(params);
  const std::uint64_t keys[] = {0x004, 0x105, 0x206, 0x307, 0x400};
  for (std::uint64_t key : keys) EXPECT_EQ(table.set_of(key), 4u) << key;
  EXPECT_NE(gpu::hrpp_set_of(0x004, 256), gpu::hrpp_set_of(0x105, 256));
  using O = ReferenceTable::Outcome;
  std::uint64_t evictions = 0;
  std::uint32_t nearest = 0;
  for (std::uint32_t i = 0; i < 4; ++i)
    EXPECT_EQ(table.insert(keys[i], static_cast<int>(10 + i), 1.0f, i + 1, evictions),
              O::kInserted);
  ASSERT_FALSE(table.lookup(keys[0], 5, nearest).empty());  // renews 0x004
  EXPECT_EQ(table.insert(keys[4], 14, 1.0f, 6, evictions), O::kInserted);
  EXPECT_EQ(evictions, 1u);
  EXPECT_TRUE(table.lookup(keys[1], 7, nearest).empty());  // 0x105 was the oldest
  for (std::uint64_t key : {keys[0], keys[2], keys[3], keys[4]})
    EXPECT_FALSE(table.lookup(key, 8, nearest).empty()) << key;
  EXPECT_EQ(table.insert(keys[0], 20, 1.0f, 9, evictions), O::kInserted);  // replaces node 10
  EXPECT_EQ(evictions, 2u);
  const std::span<const int> held = table.lookup(keys[0], 10, nearest);
  ASSERT_EQ(held.size(), 1u);
  EXPECT_EQ(held[0], 20);
  EXPECT_EQ(table.insert(keys[0], 20, 1.0f, 11, evictions), O::kPresent);
  EXPECT_EQ(table.entries(), 4u);
}

// Per-SM tables: rays in blocks of HRPP_SM_BLOCK (64) consecutive use clocks go to the K tables
// round robin; the same key in two blocks dealt to different tables makes two entries, each
// table of its own sets, and a key's table survives in it (the queue and deferred inserts).
TEST(HrppPredictor, SmTablesDealBlocksOfRaysRoundRobin) {
  constexpr std::uint32_t kTables = 3;
  EXPECT_EQ(gpu::hrpp_sm_key(5, 0, kTables), 5u);
  EXPECT_EQ(gpu::hrpp_sm_key(5, 63, kTables), 5u);
  EXPECT_EQ(gpu::hrpp_sm_key(5, 64, kTables), 5u | (std::uint64_t{1} << HRPP_KEY_BITS));
  EXPECT_EQ(gpu::hrpp_sm_key(5, 128, kTables), 5u | (std::uint64_t{2} << HRPP_KEY_BITS));
  EXPECT_EQ(gpu::hrpp_sm_key(5, 192, kTables), 5u);
  EXPECT_EQ(gpu::hrpp_sm_key(5, 100, 1), 5u);  // one table: the key as hashed
  EXPECT_EQ(gpu::hrpp_sm_key(5, 100, 0), 5u);
  gpu::PredictorParams params{};
  params.sets = 4;
  params.ways = 1;
  params.nodes = 2;
  params.policy = static_cast<std::uint32_t>(TablePolicy::kMicro21);
  params.sm_tables = kTables;
  ReferenceTable table(params);
  std::uint64_t evictions = 0;
  std::uint32_t nearest = 0;
  for (std::uint32_t clock : {0u, 64u, 128u}) {
    const std::uint64_t key = gpu::hrpp_sm_key(5, clock, kTables);
    EXPECT_EQ(table.set_of(key), (clock / 64) * 4 + gpu::hrpp_folded_set(5, 4)) << clock;
    EXPECT_EQ(table.insert(key, static_cast<int>(clock), 1.0f, clock, evictions),
              ReferenceTable::Outcome::kInserted);
  }
  EXPECT_EQ(table.entries(), 3u);
  EXPECT_EQ(evictions, 0u);
  const std::span<const int> second = table.lookup(gpu::hrpp_sm_key(5, 70, kTables), 200, nearest);
  ASSERT_FALSE(second.empty());
  EXPECT_EQ(second[0], 64);
  TableConfig config = table_preset("micro21");
  config.sm_tables = 0;
  PredictorConfig p;
  p.enabled = true;
  p.set_table(config);
  EXPECT_THROW(make_predictor_params(p, RayClass::kCamera, Aabb{glm::vec3(0.0f), glm::vec3(1.0f)}),
               Error);
}

// The distance gate's nearest hit per entry: the least t inserted under the key, none (word 0)
// for a key that came in by evicting another, and none kept without the gate.
TEST(HrppPredictor, EntriesKeepTheNearestHitForTheGate) {
  gpu::PredictorParams params{};
  params.sets = 1;
  params.ways = 1;
  params.nodes = 2;
  params.policy = static_cast<std::uint32_t>(TablePolicy::kLru);
  params.gate = 1.5f;
  ReferenceTable table(params);
  std::uint64_t evictions = 0;
  std::uint32_t nearest = 0;
  table.insert(1, 10, 4.0f, 1, evictions);
  table.insert(1, 11, 2.0f, 2, evictions);
  table.insert(1, 10, 3.0f, 3, evictions);
  ASSERT_FALSE(table.lookup(1, 4, nearest).empty());
  EXPECT_EQ(nearest, gpu::hrpp_nearest_word(2.0f));
  EXPECT_FALSE(gpu::hrpp_gated(3.0f, nearest, params.gate));  // 3 <= 1.5 × 2
  EXPECT_TRUE(gpu::hrpp_gated(3.5f, nearest, params.gate));
  EXPECT_FALSE(gpu::hrpp_gated(3.5f, 0u, params.gate));  // no hit seen yet: accepted
  EXPECT_FALSE(gpu::hrpp_gated(3.5f, nearest, 0.0f));    // gate off
  table.insert(2, 20, 8.0f, 5, evictions);  // evicts key 1
  ASSERT_FALSE(table.lookup(2, 6, nearest).empty());
  EXPECT_EQ(nearest, gpu::hrpp_nearest_word(8.0f));
  params.gate = 0.0f;
  ReferenceTable off(params);
  off.insert(1, 10, 4.0f, 1, evictions);
  ASSERT_FALSE(off.lookup(1, 2, nearest).empty());
  EXPECT_EQ(nearest, 0u);
}

}  // namespace
}  // namespace hrpp
