// hrpp trace SCENE --rays R.bin --hits H.bin [--any-hit] [--device D] [--validate]: trace a file
// of rays on the GPU and write one hit record per ray (formats: docs/FORMATS.md).
#include <algorithm>
#include <bit>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "app/commands.h"
#include "app/cli_names.h"
#include "app/hrpp_options.h"
#include "app/output_path.h"
#include "app/provenance.h"
#include "app/shared_options.h"
#include "harness/tracer.h"
#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "common/bytes.h"
#include "common/error.h"
#include "front/make_device_tracer.h"
#include "front/predicting_tracer.h"
#include "gpu/ray_query_tracer.h"
#include "gpu/ray_sorter.h"
#include "vk/vulkan_context.h"
#include "render/render_stats.h"
#include "scene/load_scene.h"
#include "trace/ray_order.h"

namespace hrpp::app {
namespace {

static_assert(std::endian::native == std::endian::little, "the ray and hit files are little-endian");

struct TraceOptions {
  SharedOptions shared;
  std::string rays;
  std::string hits;
  QueryKind query = QueryKind::kClosest;  // --any-hit: kAny
  int repeat = 1;
  NodeLayout bvh_layout = NodeLayout::kDfs;
  RayOrder reorder = RayOrder::kOff;
  HrppOptions hrpp;
  std::string stats;
};

std::vector<gpu::Ray> read_rays(const std::filesystem::path& file) {
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(file, ec);
  if (ec) throw Error(file.string() + ": cannot read rays: " + ec.message());
  if (bytes % sizeof(gpu::Ray) != 0)
    throw Error(file.string() + ": " + std::to_string(bytes) +
                " bytes is not a whole number of 32-byte ray records");
  std::vector<gpu::Ray> rays(bytes / sizeof(gpu::Ray));
  std::ifstream in(file, std::ios::binary);
  if (!in.read(reinterpret_cast<char*>(rays.data()), static_cast<std::streamsize>(bytes)))
    throw Error(file.string() + ": cannot read rays");
  return rays;
}

// --reorder: the device sort of the ray file (nullptr when off).
std::unique_ptr<RaySorter> make_sorter(VulkanContext& ctx, const GpuBvh& bvh, RayOrder order,
                                       std::size_t rays) {
  if (order == RayOrder::kOff) return nullptr;
  if (rays > RaySorter::kMaxRays)
    throw Error("--reorder: " + std::to_string(rays) + " rays exceed the " +
                std::to_string(RaySorter::kMaxRays) + " one sort takes");
  return std::make_unique<RaySorter>(ctx, bvh.bounds, rays);
}

// The device, the rays, the kernel time and the work per ray (with --count-steps, the lanes'
// use of the interior-node loop).
void print_figures(const TraceOptions& o, const VulkanContext& ctx, std::size_t rays,
                   double median, const TraversalCounters& c, bool sorted) {
  const double n = static_cast<double>(rays);
  const auto per_ray = [n](std::uint64_t v) { return n > 0 ? static_cast<double>(v) / n : 0.0; };
  std::printf("device      %s\n", ctx.info().summary().c_str());
  std::printf("rays        %zu %s queries, %llu hit%s\n", rays,
              o.query == QueryKind::kAny ? "any-hit" : "closest-hit",
              static_cast<unsigned long long>(c.hits),
              o.query == QueryKind::kAny ? " (occluded)" : "");
  const bool driver = o.shared.device_tracer == DeviceTracerKind::kRayQuery;
  std::printf("kernel      %.3f ms%s, %.2f Mrays/s (%d rays per invocation)\n", median,
              o.repeat > 1 ? " median after warm-up" : " (first dispatch: includes JIT)",
              median > 0.0 ? n / (median * 1e3) : 0.0,
              static_cast<int>(o.shared.tracer.resolved_for(ctx.info()).rays_per_invocation));
  std::printf("reorder     %s%s\n", ray_order_name(o.reorder),
              sorted ? " (the sort's device time is in the kernel time)" : "");
  std::printf("tracer      %s\n", name_in(kDeviceTracerNames, o.shared.device_tracer));
  if (!driver) std::printf("bvh nodes   %s\n", node_format_name(o.shared.nodes));
  std::printf("memory      %s\n", placement_text(ctx.memory().report().placement).c_str());
  if (driver)
    std::printf("per ray     not visible (the driver's traversal)\n");
  else
    std::printf("per ray     %.2f interior nodes, %.2f leaves, %.2f triangles\n",
                per_ray(c.interior_visited), per_ray(c.leaves_visited),
                per_ray(c.triangles_tested));
  if (o.shared.tracer.count_steps)
    std::printf("lane use    %.1f%% of the interior-node loop's lane slots (%llu steps)\n",
                100.0 * lane_use(c, ctx.info().subgroup_size),
                static_cast<unsigned long long>(c.interior_steps));
}

// The driver's acceleration structure (--tracer rayquery).
void print_structure(const AccelerationStructureStats& s) {
  std::printf("structure   the driver's: %s (%s before compaction), built in %.1f ms\n",
              format_bytes(s.bytes).c_str(), format_bytes(s.uncompacted_bytes).c_str(), s.build_ms);
}

// HRPP's lines ("off" without a summary) and their JSON. A true positive answers its ray
// (hit-any, speculative) or bounds its trace's tmax (exact hit-all): in front of the driver
// (`driver`), a query skipped or shortened.
std::string hrpp_figures(const TraceOptions& o, const PredictorConfig& predictor,
                         const std::optional<PredictorSummary>& s, bool driver,
                         nlohmann::json& json) {
  if (!s) return "off";
  json["summary"] = predictor_summary_json(*s);
  const std::uint64_t tp = s->counters.c[HRPP_PC_TRUE_POSITIVES];
  const bool bounds = o.query == QueryKind::kClosest && predictor.mode == PredictorMode::kExact;
  json["answered_without_trace"] = bounds ? 0 : tp;
  json["traced_with_shorter_tmax"] = bounds ? tp : 0;
  char line[160];
  std::snprintf(line, sizeof line,
                "            %llu rays answered without a %s, %llu %s with tmax shortened\n",
                static_cast<unsigned long long>(bounds ? 0 : tp), driver ? "query" : "traversal",
                static_cast<unsigned long long>(bounds ? tp : 0),
                driver ? "queries" : "traversals");
  return describe(predictor) + "\n" + format_summary("", *s, o.query) + line;
}

// The device tracer --tracer names (--repeat > 1: warmed up), and what it needs kept alive.
struct TraceBackend {
  std::unique_ptr<DeviceTracer> tracer;
  const RayQueryTracer* ray_query = nullptr;  // the driver's, behind HRPP's stage or not
  std::unique_ptr<RaySorter> sorter;
  std::unique_ptr<Tracer> backend;
};

TraceBackend make_backend(const TraceOptions& o, VulkanContext& ctx, const GpuBvh& bvh,
                          const PredictorConfig& predictor, std::span<const gpu::Ray> rays) {
  TraceBackend b;
  b.tracer = make_device_tracer(ctx, o.shared.device_tracer, bvh, o.shared.tracer, predictor);
  const auto* front = dynamic_cast<const PredictingTracer*>(b.tracer.get());
  b.ray_query = dynamic_cast<const RayQueryTracer*>(front ? &front->inner() : b.tracer.get());
  if (b.ray_query) {
    if (o.repeat > 1) b.tracer->warm_up();
    b.backend = std::make_unique<RayQueryBackend>(*b.tracer);
    return b;
  }
  b.sorter = make_sorter(ctx, bvh, o.reorder, rays.size());
  if (o.repeat > 1) {
    b.tracer->warm_up();
    if (b.sorter)
      b.tracer->trace(rays.first(std::min<std::size_t>(rays.size(), 64)), o.query,
                      b.sorter.get());  // the sort's and indexed kernels' JIT
  }
  // HRPP on: every run starts from an empty table (GpuBackend clears it).
  b.backend = std::make_unique<GpuBackend>(*b.tracer, b.sorter.get());
  return b;
}

void run_trace(const TraceOptions& o) {
  check_output_path(o.hits, "--hits");
  check_output_path(o.stats, "--stats");
  const PredictorConfig predictor = o.hrpp.config(o.shared.device_tracer);
  check_compute_only(o.shared, {{"--reorder", o.reorder != RayOrder::kOff},
                                {"--count-steps", o.shared.tracer.count_steps},
                                {"--bvh-layout", o.bvh_layout != NodeLayout::kDfs}});
  if (o.reorder != RayOrder::kOff && predictor.predicts(ray_file_class(o.query)))
    throw Error("--reorder: HRPP's predicted trace takes the rays in file order; use "
                "--reorder off with HRPP on");
  const std::vector<gpu::Ray> rays = read_rays(o.rays);
  const Scene scene = load_scene(o.shared.scene);
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene, o.shared.bvh), scene, o.bvh_layout,
                                     o.shared.nodes);
  VulkanContext ctx(o.shared.vulkan);
  const TraceBackend b = make_backend(o, ctx, bvh, predictor, rays);
  const std::unique_ptr<Tracer>& backend = b.backend;
  const std::unique_ptr<RaySorter>& sorter = b.sorter;
  const RayQueryTracer* ray_query = b.ray_query;

  TracerRun result;
  std::vector<double> ms;
  for (int i = 0; i < o.repeat; ++i) {
    result = backend->trace(rays, o.query);
    ms.push_back(result.ms);
  }
  // HRPP's figures come from one more run that also counts what full traversals would visit
  // (outside the timings).
  nlohmann::json hrpp_json = predictor_config_json(predictor);
  const auto savings = count_savings(*b.tracer, ray_query == nullptr, rays, o.query);
  const std::string hrpp_text = hrpp_figures(o, predictor, savings, ray_query != nullptr,
                                             hrpp_json);
  check_validation_messages(ctx);
  write_file_atomically(o.hits,
                        std::string_view(reinterpret_cast<const char*>(result.hits.data()),
                                         result.hits.size() * sizeof(gpu::Hit)),
                        "cannot write hits");

  std::sort(ms.begin(), ms.end());
  const double median = ms[ms.size() / 2];
  const TraversalCounters& c = *result.counters;
  print_figures(o, ctx, rays.size(), median, c, sorter != nullptr);
  if (ray_query) print_structure(ray_query->structure());
  std::printf("hrpp        %s", hrpp_text.c_str());
  if (!predictor.predicts(ray_file_class(o.query))) std::printf("\n");
  if (!o.stats.empty()) {
    nlohmann::json j = {{"scene", o.shared.scene},
                        {"rays", rays.size()},
                        {"query", query_kind_name(o.query)},
                        {"kernel_ms_median", median},
                        {"reorder", ray_order_name(o.reorder)},
                        {"bvh_layout", node_layout_name(o.bvh_layout)},
                        {"bvh_nodes", node_format_name(o.shared.nodes)},
                        {"hits", c.hits},
                        {"interior_visited", c.interior_visited},
                        {"leaves_visited", c.leaves_visited},
                        {"triangles_tested", c.triangles_tested},
                        {"hrpp", hrpp_json},
                        {"memory", memory_json(ctx.memory().report())},
                        {"device",
                         {{"name", ctx.info().name},
                          {"driver", ctx.info().driver},
                          {"subgroup_size", ctx.info().subgroup_size},
                          {"denorm_preserve", ctx.info().denorm_preserve}}}};
    if (o.shared.tracer.count_steps) {
      j["interior_steps"] = c.interior_steps;
      j["lane_use"] = lane_use(c, ctx.info().subgroup_size);
    }
    add_provenance(j);
    write_file_atomically(o.stats, j.dump(2) + "\n", "cannot write --stats");
  }
}

}  // namespace

void add_trace_command(CLI::App& app) {
  auto o = std::make_shared<TraceOptions>();
  CLI::App* cmd = app.add_subcommand(
      "trace", "Trace a file of rays on the GPU (32-byte records) and write hits (16-byte records)");
  add_shared_options(cmd, o->shared, SharedGroup::kDevice);
  cmd->add_option("--rays", o->rays, "Rays: {float ox, oy, oz, tmin, dx, dy, dz, tmax} each")
      ->required();
  cmd->add_option("--hits", o->hits,
                  "Hits written: {int32 prim (-1 miss), float t, u, v} each; any-hit: prim 0 "
                  "occluded, -1 free")
      ->required();
  cmd->add_flag_callback(
      "--any-hit", [o] { o->query = QueryKind::kAny; },
      "Any-hit (occlusion) queries instead of closest hit");
  cmd->add_flag("--count-steps", o->shared.tracer.count_steps,
                "Also count the interior-node loop's subgroup iterations and print the lanes' "
                "use of it (a kernel variant: the timing includes the count)");
  cmd->add_option("--repeat", o->repeat, "Trace N times after a warm-up; report the median")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--bvh-layout", o->bvh_layout,
                  "Node numbering: dfs (left subtree first) or dfs-large-first (the child with "
                  "the larger surface area first); answers are the same")
      ->transform(one_of(kNodeLayoutNames))
      ->default_str(node_layout_name(o->bvh_layout));
  cmd->add_option("--reorder", o->reorder,
                  "Sort the rays on the device before tracing (sort time counted): off, or morton "
                  "(direction octant, then the origin's Morton code); hits stay in file order")
      ->transform(one_of(kRayOrderNames))
      ->default_str(ray_order_name(o->reorder));
  cmd->add_option("--stats", o->stats, "Write the figures and the HRPP configuration as JSON");
  add_hrpp_options(cmd, o->hrpp);
  cmd->callback([o] { run_trace(*o); });
}

}  // namespace hrpp::app
