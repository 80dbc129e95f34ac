// Ray reordering and node layout: per scene and Aila–Laine batch kind
// (host/trace/ray_batches.h), the GPU trace's device time with each combination of --reorder
// (off; morton: the sort's order read by the indexed trace kernel, as hrpp trace and render do;
// morton-gather: the sort then a gather of the rays into sorted order, traced by the plain
// kernel; the sort's device time always included) and --bvh-layout (dfs, dfs-large-first),
// interleaved round by round on the same rays, medians and the ratio to (dfs, off). Every
// variant's hits must equal the baseline's bit for bit (it exits 1 otherwise). Each variant's
// lane use of the interior-node loop comes from one more, untimed, counting trace. Not a test.
//   bench_ray_order [SCENE...] [--rays N] [--repeat R] [--kinds primary,ao,diffuse] [--device D]
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "kinds_option.h"
#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "common/error.h"
#include "common/median.h"
#include "gpu/gpu_tracer.h"
#include "gpu/ray_sorter.h"
#include "vk/vulkan_context.h"
#include "scene/load_scene.h"
#include "trace/ray_batches.h"
#include "trace/ray_order.h"

namespace hrpp {
namespace {

struct Variant {
  NodeLayout layout;
  RayOrder order;
  bool gather = false;  // morton-gather: sorted copies of the rays, the plain kernel
  std::string name() const {
    return std::string(node_layout_name(layout)) + " / " + ray_order_name(order) +
           (gather ? "-gather" : "");
  }
};

struct Timed {
  std::vector<gpu::Hit> hits;
  double trace_ms = 0.0, sort_ms = 0.0;
  TraversalCounters counters;
};

Timed trace_once(GpuTracer& tracer, RaySorter& sorter, std::span<const gpu::Ray> rays,
                 const Variant& v, QueryKind query) {
  Timed t;
  if (!v.gather) {
    GpuTraceResult r = tracer.trace(rays, query, v.order == RayOrder::kOff ? nullptr : &sorter);
    t.hits = std::move(r.hits);
    t.trace_ms = r.kernel_ms - r.sort_ms;
    t.sort_ms = r.sort_ms;
    t.counters = r.counters;
    return t;
  }
  const RaySortResult s = sorter.sort(rays);
  const GpuTraceResult r = tracer.trace(s.rays, query);
  t.hits = hits_in_queue_order(r.hits, s.order);
  t.trace_ms = r.kernel_ms;
  t.sort_ms = s.kernel_ms;
  t.counters = r.counters;
  return t;
}

// Each variant's lane use of the interior-node loop: one more, untimed trace by the layout's
// counting tracer (GpuTracerConfig::count_steps: a kernel variant that counts subgroup steps).
std::vector<double> lane_uses(std::unique_ptr<GpuTracer> (&counting)[2], RaySorter& sorter,
                              std::span<const gpu::Ray> batch, const std::vector<Variant>& variants,
                              QueryKind query, std::uint32_t subgroup_size) {
  std::vector<double> uses;
  for (const Variant& v : variants) {
    const int l = v.layout == NodeLayout::kDfs ? 0 : 1;
    uses.push_back(
        lane_use(trace_once(*counting[l], sorter, batch, v, query).counters, subgroup_size));
  }
  return uses;
}

int run_scene(VulkanContext& ctx, const std::string& name, std::size_t rays, int repeat,
              const std::vector<std::string>& kinds) {
  const Scene scene = load_scene(name);
  const Bvh bvh = build_bvh(scene, BvhConfig{});
  const std::vector<Variant> variants = {{NodeLayout::kDfs, RayOrder::kOff},
                                         {NodeLayout::kDfs, RayOrder::kMorton},
                                         {NodeLayout::kDfs, RayOrder::kMorton, true},
                                         {NodeLayout::kDfsLargeFirst, RayOrder::kOff},
                                         {NodeLayout::kDfsLargeFirst, RayOrder::kMorton}};
  GpuBvh layouts[2] = {make_gpu_layout(bvh, scene, NodeLayout::kDfs),
                       make_gpu_layout(bvh, scene, NodeLayout::kDfsLargeFirst)};
  std::unique_ptr<GpuTracer> tracers[2], counting[2];
  GpuTracerConfig counts;
  counts.count_steps = true;
  for (int l = 0; l < 2; ++l) {
    tracers[l] = std::make_unique<GpuTracer>(ctx, layouts[l]);
    tracers[l]->warm_up();
    counting[l] = std::make_unique<GpuTracer>(ctx, layouts[l], counts);
  }
  RayBatchConfig bc;
  bc.secondary_count = rays;
  const RayBatches b = make_ray_batches(scene, layouts[0], bc);
  RaySorter sorter(ctx, layouts[0].bounds, std::max(b.primary.size(), rays));
  int failures = 0;
  for (const std::string& kind : kinds) {
    const RayKind k = *ray_kind_named(kind);  // --kinds lets only kinds through
    const QueryKind query = query_kind(k);
    const std::span<const gpu::Ray> batch = rays_of_kind(b, k);
    std::vector<std::vector<double>> total(variants.size()), sort(variants.size());
    std::vector<gpu::Hit> baseline;
    // JIT warm-up of the sort kernels, the gather and the indexed trace kernels
    sorter.sort(batch);
    const std::size_t few = std::min<std::size_t>(batch.size(), 64);
    for (auto& tracer : tracers) tracer->trace(batch.first(few), query, &sorter);
    for (int round = 0; round < repeat; ++round)
      for (std::size_t v = 0; v < variants.size(); ++v) {
        const int l = variants[v].layout == NodeLayout::kDfs ? 0 : 1;
        const Timed t = trace_once(*tracers[l], sorter, batch, variants[v], query);
        total[v].push_back(t.trace_ms + t.sort_ms);
        sort[v].push_back(t.sort_ms);
        if (v == 0 && round == 0) baseline = t.hits;
        if (t.hits.size() != baseline.size() ||
            std::memcmp(t.hits.data(), baseline.data(), baseline.size() * sizeof(gpu::Hit)) != 0) {
          std::fprintf(stderr, "%s %s %s: hits differ from dfs / off\n", name.c_str(),
                       kind.c_str(), variants[v].name().c_str());
          ++failures;
        }
      }
    const std::vector<double> uses =
        lane_uses(counting, sorter, batch, variants, query, ctx.info().subgroup_size);
    const double base = median(total[0]);
    for (std::size_t v = 0; v < variants.size(); ++v) {
      const double ms = median(total[v]);
      std::printf("%-12s %-8s %-24s %9.2f ms (sort %6.2f) %7.2f Mrays/s  %.3fx  lanes %4.1f%%\n",
                  scene.name.c_str(), kind.c_str(), variants[v].name().c_str(), ms, median(sort[v]),
                  ms > 0 ? static_cast<double>(batch.size()) / (ms * 1e3) : 0.0,
                  ms > 0 ? base / ms : 0.0, 100.0 * uses[v]);
    }
  }
  return failures;
}

}  // namespace
}  // namespace hrpp

int main(int argc, char** argv) {
  std::vector<std::string> scenes = {"bunny"};
  std::vector<std::string> kinds = {"primary", "ao", "diffuse"};
  std::size_t rays = std::size_t{1} << 20;
  int repeat = 5;
  hrpp::VulkanOptions vk;
  CLI::App app{"Ray reordering and node layouts: GPU trace time with and without"};
  app.add_option("scenes", scenes, "Scenes (names in scenes/, files)")->capture_default_str();
  app.add_option("--rays", rays, "Rays per AO / diffuse batch (primary: 1024x1024)")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 22));
  app.add_option("--repeat", repeat, "Interleaved rounds; medians are printed")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  hrpp::bench::add_kinds_option(app, kinds);
  app.add_option("--device", vk.device, "Vulkan device (index or name substring)");
  CLI11_PARSE(app, argc, argv);
  try {
    hrpp::VulkanContext ctx(vk);
    std::printf("device %s; ratio: (dfs / off) time / this time, > 1 is faster\n",
                ctx.info().name.c_str());
    int failures = 0;
    for (const std::string& s : scenes) failures += hrpp::run_scene(ctx, s, rays, repeat, kinds);
    return failures == 0 ? 0 : 1;
  } catch (const hrpp::Error& e) {
    std::fprintf(stderr, "bench_ray_order: %s\n", e.what());
    return 1;
  }
}
