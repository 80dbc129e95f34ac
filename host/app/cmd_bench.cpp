// hrpp bench SCENE [--rays N] [--kinds primary,ao,diffuse] [--json FILE]: ray-tracing speed in
// the style of Aila and Laine (HPG 2009) and tinybvh's speed test. Fixed batches of one view
// (trace/ray_batches.h), each traced by the CPU reference (all threads), Embree (all threads,
// when the build has it) and the Vulkan device (GpuTracer; with --tracer rayquery also the
// driver's ray queries, RayQueryTracer). Every tracer is warmed up, then timed
// `--repeat` times over the whole batch (median reported), and its hits are checked against the
// CPU reference on a subset; mismatches are printed loudly, recorded in the JSON and fail the
// command unless --warn-mismatches. The harness (tracers, validation, timing) is host/harness/.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli_names.h"
#include "app/commands.h"
#include "app/output_path.h"
#include "app/provenance.h"
#include "app/hrpp_options.h"
#include "app/shared_options.h"
#include "harness/time_tracer.h"
#include "harness/tracer.h"
#include "harness/validation.h"
#include "bvh/binned_sah_builder.h"
#include "bvh/bvh_stats.h"
#include "bvh/gpu_layout.h"
#include "common/bytes.h"
#include "common/error.h"
#include "common/free_array.h"
#include "common/median.h"
#include "common/task_pool.h"
#include "front/make_device_tracer.h"
#include "gpu/gpu_tracer.h"
#include "gpu/ray_query_tracer.h"
#include "vk/vulkan_context.h"
#include "render/render_stats.h"
#include "reference/embree_tracer.h"
#include "scene/load_scene.h"
#include "trace/ray_batches.h"

namespace hrpp::app {
namespace {

struct BenchOptions {
  SharedOptions shared;
  std::size_t rays = std::size_t{1} << 20;
  std::vector<std::string> kinds = {"primary", "ao", "diffuse"};
  std::string json;
  std::string save_rays;  // directory for the batches and the triangle dump
  int repeat = 3;
  std::size_t validate = 100000;  // rays checked against the CPU reference; 0: all
  int threads = 0;                // CPU reference and Embree threads; 0: all hardware threads
  std::uint64_t seed = 1;
  bool jitter = false;
  float ao_radius = 0.1f;
  bool no_embree = false;
  bool no_gpu = false;
  bool warn_mismatches = false;  // mismatches against the CPU reference only warn
  HrppOptions hrpp;
  TableSharing cpu_tables = TableSharing::kPerThread;  // cpu-hrpp, emb-hrpp
};

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

RayKind parse_kind(const std::string& s) {
  if (const std::optional<RayKind> k = ray_kind_named(s)) return *k;
  throw Error("--kinds: unknown kind '" + s + "' (primary, ao, diffuse)");
}

nlohmann::json tracer_json(const TracerResult& t) {
  nlohmann::json j = {{"tracer", t.name},
                      {"mrays_per_s", t.mrays},
                      {"median_ms", t.median_ms},
                      {"runs_ms", t.ms},
                      {"timing", t.timing},
                      {"hits", t.hits},
                      {"validation",
                       {{"checked", t.validation.checked},
                        {"exact", t.validation.exact},
                        {"ties", t.validation.ties},
                        {"mismatches", t.validation.mismatches},
                        {"examples", t.validation.examples}}}};
  if (t.counters)
    j["counters"] = {{"rays", t.counters->rays},
                     {"interior_visited", t.counters->interior_visited},
                     {"leaves_visited", t.counters->leaves_visited},
                     {"triangles_tested", t.counters->triangles_tested},
                     {"hits", t.counters->hits}};
  if (t.predictor)
    j["predictor"] = {{"probes", t.predictor->c[HRPP_PC_PROBES]},
                      {"predictor_hits", t.predictor->c[HRPP_PC_PREDICTOR_HITS]},
                      {"true_positives", t.predictor->c[HRPP_PC_TRUE_POSITIVES]}};
  return j;
}

// The machine, printed first so that a crash later still says where it ran.
nlohmann::json probe_machine(int threads) {
  const std::string cpu = cpu_model();
  std::printf("machine     %s, %u hardware threads; CPU reference and Embree on %d threads\n",
              cpu.c_str(), std::thread::hardware_concurrency(), threads);
  return {{"cpu", cpu},
          {"hardware_threads", std::thread::hardware_concurrency()},
          {"cpu_tracer_threads", threads}};
}

// The Vulkan device, or none (--no-gpu, or no device: the GPU tracers are skipped).
std::unique_ptr<VulkanContext> open_device(const BenchOptions& o, nlohmann::json& machine) {
  if (o.no_gpu) {
    if (o.shared.vulkan.ray_query) throw Error("--tracer rayquery: the device's ray queries, not "
                                               "with --no-gpu");
    std::printf("vulkan      off (--no-gpu)\n");
    return nullptr;
  }
  try {
    auto ctx = std::make_unique<VulkanContext>(o.shared.vulkan);
    const DeviceInfo& d = ctx->info();
    std::printf("vulkan      %s\n", d.summary().c_str());
    // Where the tracers' buffers live (--memory): to look into a GPU's slower later query kinds
    // (bench/GPU.md).
    const MemoryPlacement& placement = ctx->memory().report().placement;
    std::printf("memory      %s; heap %s (%s)\n", placement_text(placement).c_str(),
                format_bytes(d.heap_bytes).c_str(),
                d.heap_budget    ? "budget"
                : d.heap_is_host ? "the host's memory"
                                 : "reported");
    machine["vulkan_memory_mode"] = placement.mode;
    machine["vulkan_memory_placement"] = placement_json(placement);
    machine["vulkan_buffers_device_local"] = d.device_memory.device_local();
    machine["vulkan_heap_bytes"] = d.heap_bytes;
    machine["vulkan_device"] = d.name;
    machine["vulkan_driver"] = d.driver;
    machine["vulkan_denorm_preserve"] = d.denorm_preserve;
    machine["vulkan_device_type"] = d.type_name();
    return ctx;
  } catch (const Error& e) {
    if (o.shared.vulkan.ray_query) throw;  // --tracer rayquery asked for the device's own
    std::printf("vulkan      not available: %s (GPU skipped)\n", e.what());
    machine["vulkan_device"] = nullptr;
    return nullptr;
  }
}

nlohmann::json describe_scene(const BenchOptions& o, const Scene& scene, const Bvh& base) {
  const BvhStats stats = compute_bvh_stats(base, o.shared.bvh);
  std::printf("scene       %s: %zu triangles (%u degenerate), BVH %.1f ms, %u interior, %u leaves, "
              "depth %u, %s nodes\n",
              scene.name.c_str(), scene.triangles.size(), stats.degenerate, base.build_ms,
              stats.interior_nodes, stats.leaves, stats.max_depth, node_format_name(o.shared.nodes));
  return {{"name", scene.name},
          {"spec", o.shared.scene},
          {"triangles", scene.triangles.size()},
          {"degenerate", stats.degenerate},
          {"bvh_build_ms", base.build_ms},
          {"bvh_interior_nodes", stats.interior_nodes},
          {"bvh_leaves", stats.leaves},
          {"bvh_max_depth", stats.max_depth},
          {"bvh_sah_cost", stats.sah_cost},
          {"bvh_nodes", node_format_name(o.shared.nodes)}};
}

// The backends a bench compares and what they need to stay alive; tracers[0] is the CPU reference.
struct Backends {
  std::unique_ptr<EmbreeTracer> embree;
  std::unique_ptr<GpuTracer> gpu;
  std::unique_ptr<DeviceTracer> hrpp;  // HRPP on: the stage in front of a second GPU tracer
  std::unique_ptr<RayQueryTracer> ray_query;  // --tracer rayquery: the driver's traversal too
  std::unique_ptr<DeviceTracer> ray_query_hrpp;  // and with HRPP on, the stage in front of it
  PredictorConfig predictor;
  std::vector<std::unique_ptr<Tracer>> tracers;
};

Backends make_backends(const BenchOptions& o, const Scene& scene, const GpuBvh& bvh,
                       VulkanContext* ctx, int threads, nlohmann::json& report) {
  Backends b;
  b.tracers.push_back(std::make_unique<CpuReferenceTracer>(bvh, threads));
  b.predictor = o.hrpp.config();
  if (b.predictor.enabled)
    b.tracers.push_back(std::make_unique<CpuHrppTracer>(bvh, b.predictor, threads, o.cpu_tables));
  if (o.no_embree) {
    std::printf("embree      off (--no-embree)\n");
  } else if (!embree_available()) {
    std::printf("embree      Embree not available: skipped\n");
  } else {
    b.embree = std::make_unique<EmbreeTracer>(scene);
    std::printf("embree      %s, build %.1f ms (quality high, rtcIntersect1/rtcOccluded1)\n",
                embree_version().c_str(), b.embree->build_ms());
    report["embree"] = {{"version", embree_version()}, {"build_ms", b.embree->build_ms()}};
    b.tracers.push_back(std::make_unique<EmbreeBackend>(*b.embree, threads));
    if (b.predictor.enabled)
      b.tracers.push_back(
          std::make_unique<CpuHrppTracer>(bvh, b.predictor, threads, o.cpu_tables,
                                          b.embree.get()));
  }
  if (ctx) {
    b.gpu = std::make_unique<GpuTracer>(*ctx, bvh, o.shared.tracer);
    b.gpu->warm_up();
    b.tracers.push_back(std::make_unique<GpuBackend>(*b.gpu));
  }
  if (ctx && o.shared.device_tracer == DeviceTracerKind::kRayQuery) {
    b.ray_query = std::make_unique<RayQueryTracer>(*ctx, bvh);
    b.ray_query->warm_up();
    const AccelerationStructureStats& s = b.ray_query->structure();
    std::printf("rayquery    the driver's structure %s (%s before compaction), built in %.1f ms; "
                "the project's BVH %s\n",
                format_bytes(s.bytes).c_str(), format_bytes(s.uncompacted_bytes).c_str(),
                s.build_ms, format_bytes(bvh.bytes()).c_str());
    report["rayquery"] = {{"structure_bytes", s.bytes},
                          {"uncompacted_bytes", s.uncompacted_bytes},
                          {"scratch_bytes", s.scratch_bytes},
                          {"build_ms", s.build_ms},
                          {"bvh_bytes", bvh.bytes()}};
    b.tracers.push_back(std::make_unique<RayQueryBackend>(*b.ray_query));
    if (b.predictor.enabled) {
      b.ray_query_hrpp =
          make_device_tracer(*ctx, DeviceTracerKind::kRayQuery, bvh, o.shared.tracer,
                             o.hrpp.config(DeviceTracerKind::kRayQuery));
      b.ray_query_hrpp->warm_up();
      b.tracers.push_back(std::make_unique<RayQueryBackend>(*b.ray_query_hrpp));
    }
  }
  if (ctx && b.predictor.enabled) {
    b.hrpp = make_device_tracer(*ctx, DeviceTracerKind::kCompute, bvh, o.shared.tracer,
                                b.predictor);
    b.hrpp->warm_up();
    std::printf("hrpp        %s; ray classes: %s\n", describe(b.predictor).c_str(),
                ray_class_list(b.predictor.classes).c_str());
    b.tracers.push_back(std::make_unique<GpuBackend>(*b.hrpp));
  }
  report["hrpp"] = predictor_config_json(b.predictor);
  report["hrpp"]["rays"] = ray_class_list(b.predictor.classes);
  return b;
}

// Batches: the primary grid is the smallest near-square one with >= N pixels, cut to N rays.
RayBatches make_batches(const BenchOptions& o, const Scene& scene, const GpuBvh& bvh, int threads,
                        nlohmann::json& report) {
  RayBatchConfig bc;
  bc.width = static_cast<std::uint32_t>(std::ceil(std::sqrt(static_cast<double>(o.rays))));
  bc.height = static_cast<std::uint32_t>((o.rays + bc.width - 1) / bc.width);
  bc.secondary_count = o.rays;
  bc.seed = o.seed;
  bc.jitter = o.jitter;
  bc.ao_radius_fraction = o.ao_radius;
  bc.threads = threads;
  const auto gen_start = Clock::now();
  RayBatches batches = make_ray_batches(scene, bvh, bc);
  batches.primary.resize(o.rays);
  batches.primary_hits.resize(o.rays);
  std::printf("batches     primary %ux%u%s (%s), %zu of %zu hit; ao tmax %.6g (%.3g x diagonal "
              "%.6g); diffuse tmax inf; seed %llu; generated in %.0f ms\n",
              bc.width, bc.height, bc.width * bc.height != o.rays ? " cut to --rays" : "",
              o.jitter ? "jittered" : "pixel centres", batches.primary_hit_count,
              static_cast<std::size_t>(bc.width) * bc.height, batches.ao_tmax, o.ao_radius,
              batches.scene_diagonal, static_cast<unsigned long long>(o.seed), ms_since(gen_start));
  report["batches"] = {{"rays", o.rays},
                       {"primary_width", bc.width},
                       {"primary_height", bc.height},
                       {"jitter", o.jitter},
                       {"primary_hits", batches.primary_hit_count},
                       {"ao_tmax", batches.ao_tmax},
                       {"ao_radius_fraction", o.ao_radius},
                       {"scene_diagonal", batches.scene_diagonal},
                       {"seed", o.seed},
                       {"repeat", o.repeat},
                       {"validate", o.validate}};
  return batches;
}

// --save-rays DIR: the batches as ray files and the scene's triangle dump (docs/FORMATS.md), so
// another tracer (bench/embree_harness.cpp, `hrpp trace`) can run on exactly these rays.
void save_batches(const std::string& dir, const Scene& scene, const RayBatches& batches) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error("--save-rays: cannot create " + dir + ": " + ec.message());
  const auto save = [&](const char* name, const std::vector<gpu::Ray>& rays) {
    write_file_atomically(dir + "/" + name + ".rays",
                          std::string_view(reinterpret_cast<const char*>(rays.data()),
                                           rays.size() * sizeof(gpu::Ray)),
                          "--save-rays: cannot write");
  };
  save("primary", batches.primary);
  save("ao", batches.ao.rays);
  save("diffuse", batches.diffuse.rays);
  write_triangle_dump(scene, dir + "/triangles.bin");
  std::printf("saved       %s/{primary,ao,diffuse}.rays and triangles.bin\n", dir.c_str());
}

// Every tracer over one batch, each validated against the CPU reference (tracers[0]).
std::vector<TracerResult> time_tracers(const BenchOptions& o, Backends& b,
                                       std::span<const gpu::Ray> rays, QueryKind kind,
                                       float scene_diagonal) {
  const std::vector<std::size_t> subset = spread_subset(rays.size(), o.validate);

  std::vector<TracerResult> results;
  std::vector<gpu::Hit> ref_hits, hits;
  for (const std::unique_ptr<Tracer>& t : b.tracers) {
    const bool hrpp = t->kind() == TracerKind::kGpuHrpp || t->kind() == TracerKind::kCpuHrpp ||
                      t->kind() == TracerKind::kRayQueryHrpp ||
                      t->kind() == TracerKind::kEmbreeHrpp;
    if (hrpp && !b.predictor.predicts(ray_file_class(kind))) continue;
    const bool reference = t->kind() == TracerKind::kCpuReference;
    TracerResult r = time_tracer(*t, rays, kind, o.repeat, reference ? ref_hits : hits);
    if (reference) {
      r.validation.checked = r.validation.exact = subset.size();
    } else {
      r.validation = validate(rays, ref_hits, hits, subset, kind, scene_diagonal);
    }
    r.speculative = hrpp && kind == QueryKind::kClosest &&
                    b.predictor.mode == PredictorMode::kSpeculative;
    results.push_back(std::move(r));
  }
  return results;
}

// HRPP: one more run from empty tables that counts the savings (outside the timings).
std::optional<PredictorSummary> count_hrpp(Backends& b, std::span<const gpu::Ray> rays,
                                           QueryKind kind) {
  if (!b.hrpp) return std::nullopt;
  return count_savings(*b.hrpp, true, rays, kind);
}

const TracerResult* find(const std::vector<TracerResult>& results, TracerKind kind) {
  for (const TracerResult& r : results)
    if (r.kind == kind) return &r;
  return nullptr;
}

// The table rows of one batch (mismatch examples on stderr); returns the mismatches counted.
std::size_t print_rows(const char* kname, std::size_t rays, QueryKind kind,
                       const std::vector<TracerResult>& results, nlohmann::json& kj) {
  std::size_t mismatches = 0;
  bool first = true;
  for (const TracerResult& r : results) {
    std::printf("%-8s %9s %-7s %-8s %9.2f %10.1f %9zu %9zu %6zu %10zu%s\n", first ? kname : "",
                first ? std::to_string(rays).c_str() : "", first ? query_kind_name(kind) : "",
                r.name.c_str(), r.mrays, r.median_ms, r.hits, r.validation.checked,
                r.validation.ties, r.validation.mismatches,
                !r.validation.mismatches ? ""
                : r.speculative          ? "  (speculative HRPP: wrong predicted hits)"
                                         : "  <-- MISMATCHES vs CPU reference");
    first = false;
    kj["tracers"].push_back(tracer_json(r));
    if (!r.speculative) mismatches += r.validation.mismatches;
    for (const std::string& ex : r.validation.examples)
      std::fprintf(stderr, "hrpp bench: %s %s %s: %s\n",
                   r.speculative ? "speculative HRPP, wrong prediction:" : "MISMATCH", kname,
                   r.name.c_str(), ex.c_str());
  }
  return mismatches;
}

// HRPP inline on the CPU (`on`: cpu-hrpp or emb-hrpp) against the same tracer without it
// (`off`) on the same threads and rays; `key`: the JSON's.
void print_cpu_hrpp(const std::vector<TracerResult>& results, TracerKind off_kind,
                    TracerKind on_kind, const char* key, nlohmann::json& kj) {
  const TracerResult* off = find(results, off_kind);
  const TracerResult* on = find(results, on_kind);
  if (!off || !on || !on->predictor || off->median_ms <= 0.0) return;
  const gpu::PredictorCounters& p = *on->predictor;
  const double probes = static_cast<double>(std::max<std::uint64_t>(p.c[HRPP_PC_PROBES], 1));
  const double ratio = on->median_ms / off->median_ms;
  std::printf("  hrpp      %s/%s %.3f (wall, same run); probes %llu: predictor hits "
              "%.1f%%, true positives %.1f%%, inserts %llu\n",
              on->name.c_str(), off->name.c_str(), ratio,
              static_cast<unsigned long long>(p.c[HRPP_PC_PROBES]),
              100.0 * static_cast<double>(p.c[HRPP_PC_PREDICTOR_HITS]) / probes,
              100.0 * static_cast<double>(p.c[HRPP_PC_TRUE_POSITIVES]) / probes,
              static_cast<unsigned long long>(p.c[HRPP_PC_INSERTS]));
  kj[key] = {{"time_over_off", ratio},
                    {"probes", p.c[HRPP_PC_PROBES]},
                    {"predictor_hits", p.c[HRPP_PC_PREDICTOR_HITS]},
                    {"true_positives", p.c[HRPP_PC_TRUE_POSITIVES]},
                    {"inserts", p.c[HRPP_PC_INSERTS]}};
}

// Per ray work, HRPP figures and ratios under the rows of one batch.
void print_ratios(const std::vector<TracerResult>& results,
                  const std::optional<PredictorSummary>& hrpp_summary, QueryKind kind,
                  nlohmann::json& kj) {
  const TracerResult* emb = find(results, TracerKind::kEmbree);
  const TracerResult* gpu = find(results, TracerKind::kGpu);
  const TracerResult* gpu_hrpp = find(results, TracerKind::kGpuHrpp);
  if (gpu && gpu->counters && gpu->counters->rays > 0) {
    const double n = static_cast<double>(gpu->counters->rays);
    std::printf("%-8s %9s %-7s gpu per ray: %.2f interior nodes, %.2f leaves, %.2f triangles\n",
                "", "", "", static_cast<double>(gpu->counters->interior_visited) / n,
                static_cast<double>(gpu->counters->leaves_visited) / n,
                static_cast<double>(gpu->counters->triangles_tested) / n);
  }
  if (hrpp_summary) {
    std::printf("%s", format_summary("  hrpp", *hrpp_summary, kind).c_str());
    kj["hrpp"] = predictor_summary_json(*hrpp_summary);
    if (gpu && gpu->mrays > 0.0 && gpu_hrpp) {
      std::printf("  hrpp      gpu-hrpp/gpu %.3f (kernel time, same run)\n",
                  gpu_hrpp->mrays / gpu->mrays);
      kj["hrpp"]["speedup"] = gpu_hrpp->mrays / gpu->mrays;
    }
  }
  print_cpu_hrpp(results, TracerKind::kCpuReference, TracerKind::kCpuHrpp, "cpu_hrpp", kj);
  print_cpu_hrpp(results, TracerKind::kEmbree, TracerKind::kEmbreeHrpp, "embree_hrpp", kj);
  if (gpu && emb && emb->mrays > 0.0) {
    std::printf("%-8s %9s %-7s gpu/embree %.3f\n", "", "", "", gpu->mrays / emb->mrays);
    kj["gpu_over_embree"] = gpu->mrays / emb->mrays;
  }
  const TracerResult* driver = find(results, TracerKind::kRayQuery);
  if (gpu && driver && driver->mrays > 0.0) {
    std::printf("%-8s %9s %-7s gpu/rayquery %.3f (kernel time, same run)\n", "", "", "",
                gpu->mrays / driver->mrays);
    kj["gpu_over_rayquery"] = gpu->mrays / driver->mrays;
  }
  const TracerResult* driver_hrpp = find(results, TracerKind::kRayQueryHrpp);
  if (driver && driver_hrpp && driver->mrays > 0.0) {
    std::printf("%-8s %9s %-7s rq-hrpp/rayquery %.3f (kernel time, same run)\n", "", "", "",
                driver_hrpp->mrays / driver->mrays);
    kj["rayquery_hrpp_speedup"] = driver_hrpp->mrays / driver->mrays;
  }
}

// One batch through every tracer: rows, figures, JSON; returns the mismatches counted.
std::size_t bench_kind(const BenchOptions& o, Backends& b, const RayBatches& batches, RayKind kind,
                       nlohmann::json& report) {
  const QueryKind query = query_kind(kind);
  const std::span<const gpu::Ray> rays = rays_of_kind(batches, kind);
  const char* kname = ray_kind_name(kind);
  if (rays.empty()) {
    std::printf("%-8s no rays: no primary ray hit the scene\n", kname);
    report["kinds"].push_back({{"kind", kname}, {"rays", 0}});
    return 0;
  }
  const std::vector<TracerResult> results = time_tracers(o, b, rays, query, batches.scene_diagonal);
  const std::optional<PredictorSummary> hrpp_summary = count_hrpp(b, rays, query);
  nlohmann::json kj = {{"kind", kname},
                       {"rays", rays.size()},
                       {"query", query_kind_name(query)},
                       {"tracers", nlohmann::json::array()}};
  const std::size_t mismatches = print_rows(kname, rays.size(), query, results, kj);
  print_ratios(results, hrpp_summary, query, kj);
  report["kinds"].push_back(std::move(kj));
  return mismatches;
}

void run_bench(const BenchOptions& o) {
  check_output_path(o.json, "--json");
  std::vector<RayKind> kinds;
  for (const std::string& k : o.kinds) kinds.push_back(parse_kind(k));
  if (o.rays == 0) throw Error("--rays: must be at least 1");
  const int threads = resolve_threads(o.threads);

  nlohmann::json report;
  report["machine"] = probe_machine(threads);
  const std::unique_ptr<VulkanContext> ctx = open_device(o, report["machine"]);
  // The bench traces rays only: without the shading data and with the base tree consumed by the
  // layout, the host holds the triangles and the two BVHs (hrpp's and Embree's) at a 50M-triangle
  // scale (study/build_scaling.py).
  Scene scene = load_scene(o.shared.scene);
  free_array(scene.shading);
  Bvh base = build_bvh(scene, o.shared.bvh);
  report["scene"] = describe_scene(o, scene, base);
  const GpuBvh bvh = make_gpu_layout(std::move(base), scene, NodeLayout::kDfs, o.shared.nodes);
  Backends backends = make_backends(o, scene, bvh, ctx.get(), threads, report);
  const RayBatches batches = make_batches(o, scene, bvh, threads, report);
  if (!o.save_rays.empty()) save_batches(o.save_rays, scene, batches);

  std::printf("\n%-8s %9s %-7s %-8s %9s %10s %9s %9s %6s %10s\n", "kind", "rays", "query",
              "tracer", "Mrays/s", "median ms", "hits", "checked", "ties", "mismatches");
  std::size_t total_mismatches = 0;
  report["kinds"] = nlohmann::json::array();
  for (const RayKind kind : kinds) total_mismatches += bench_kind(o, backends, batches, kind, report);

  std::printf("\ntiming: median of %d runs after a warm-up; cpu-ref and embree: wall clock on %d "
              "threads (cpu-hrpp, emb-hrpp: HRPP inline in front of the CPU traversal, of Embree; "
              "per-thread tables, emptied before each run); gpu: device "
              "timestamps (kernel time). validation: %s rays per kind vs the "
              "CPU reference (t within 1e-5 relative; same t, other triangle = tie)\n",
              o.repeat, threads, o.validate == 0 ? "all" : std::to_string(o.validate).c_str());
  report["total_mismatches"] = total_mismatches;
  if (total_mismatches > 0) {
    std::printf("!! %zu MISMATCHES against the CPU reference (examples on stderr)\n",
                total_mismatches);
    std::fprintf(stderr, "hrpp bench: %zu mismatches against the CPU reference\n",
                 total_mismatches);
  }
  add_provenance(report);
  if (!o.json.empty()) write_file_atomically(o.json, report.dump(2) + "\n", "cannot write --json");
  if (!o.warn_mismatches && total_mismatches > 0)
    throw Error(std::to_string(total_mismatches) +
                " mismatches against the CPU reference (--warn-mismatches: report them and exit 0)");
  if (ctx) check_validation_messages(*ctx);
}

}  // namespace

void add_bench_command(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench",
      "Mrays/s on fixed primary / AO / diffuse batches: CPU reference, Embree, Vulkan device");
  cmd->add_option("--rays", o->rays,
                  "Rays per batch; primaries on the smallest near-square grid with >= N pixels "
                  "(2^20: 1024x1024)")
      ->capture_default_str();
  cmd->add_option("--kinds", o->kinds, "Batches: primary (closest), ao (any), diffuse (closest)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--json", o->json, "Write every figure, the machine and the validation as JSON");
  cmd->add_option("--save-rays", o->save_rays,
                  "Write the batches (DIR/primary.rays, ao.rays, diffuse.rays) and the triangle "
                  "dump (DIR/triangles.bin) for another tracer");
  cmd->add_option("--repeat", o->repeat, "Timed runs per tracer and batch (median reported)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--check-rays", o->validate,
                  "Rays per batch checked against the CPU reference (evenly spread; 0: all)")
      ->capture_default_str();
  cmd->add_option("--threads", o->threads, "CPU reference and Embree threads (0: all)")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Batch seed")->capture_default_str();
  cmd->add_flag("--jitter", o->jitter, "Jittered primaries (default: pixel centres)");
  cmd->add_option("--ao-radius", o->ao_radius, "AO tmax as a fraction of the scene diagonal")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--no-embree", o->no_embree, "Skip Embree");
  cmd->add_flag("--no-gpu", o->no_gpu, "Skip the Vulkan device");
  cmd->add_flag("--warn-mismatches", o->warn_mismatches,
                "Report mismatches against the CPU reference and exit 0 (default: exit 1)");
  cmd->add_option("--cpu-tables", o->cpu_tables,
                  "HRPP on the CPU (cpu-hrpp, emb-hrpp): per-thread tables, or one table per ray "
                  "class shared by the threads (striped locks)")
      ->transform(one_of(kTableSharingNames))
      ->default_str(name_in(kTableSharingNames, o->cpu_tables));
  add_shared_options(cmd, o->shared, SharedGroup::kDevice);
  add_hrpp_options(cmd, o->hrpp);
  cmd->callback([o] { run_bench(*o); });
}

}  // namespace hrpp::app
