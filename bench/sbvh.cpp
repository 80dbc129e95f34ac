// Spatial splits: per scene, the object-split BVH (binned SAH) against the
// SBVH (--bvh-splits spatial) side by side: SAH cost, build time on --threads threads
// (interleaved rounds, best and median), references per triangle and node counts; then the GPU
// trace's device time and Mrays/s over each BVH on the same Aila-Laine batches
// (host/trace/ray_batches.h), interleaved round by round, medians and the ratio. Closest hits
// must be equal (triangle, t, u, v) and any-hit verdicts too (it exits 1 otherwise). Not a test.
//   bench_sbvh [SCENE...] [--rays N] [--repeat R] [--build-repeat B] [--threads T]
//              [--kinds primary,ao,diffuse] [--device D]
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "kinds_option.h"
#include "bvh/binned_sah_builder.h"
#include "bvh/bvh_stats.h"
#include "bvh/gpu_layout.h"
#include "common/median.h"
#include "common/error.h"
#include "gpu/gpu_tracer.h"
#include "vk/vulkan_context.h"
#include "scene/load_scene.h"
#include "trace/ray_batches.h"

namespace hrpp {
namespace {

struct Options {
  std::vector<std::string> scenes = {"bunny", "lamborghini", "dragon"};
  std::vector<std::string> kinds = {"primary", "ao", "diffuse"};
  std::size_t rays = std::size_t{1} << 20;
  int repeat = 5, build_repeat = 5, threads = 2;
};

const char* kSplitNames[2] = {"object", "spatial"};

// Builds both BVHs build_repeat times, interleaved; prints a line each; returns the last ones.
std::vector<Bvh> build_both(const Scene& scene, const Options& o) {
  std::vector<BvhConfig> configs(2);
  std::vector<std::vector<double>> ms(2);
  std::vector<Bvh> bvhs(2);
  for (int s = 0; s < 2; ++s) {
    configs[s].threads = o.threads;
    configs[s].splits = s == 0 ? BvhSplits::kObject : BvhSplits::kSpatial;
    build_bvh(scene, configs[s]);  // warm-up
  }
  for (int round = 0; round < o.build_repeat; ++round)
    for (int s = 0; s < 2; ++s) {
      bvhs[s] = build_bvh(scene, configs[s]);
      ms[s].push_back(bvhs[s].build_ms);
    }
  for (int s = 0; s < 2; ++s) {
    const BvhStats st = compute_bvh_stats(bvhs[s], configs[s]);
    std::printf("%-12s build %-8s SAH %8.3f  %9.1f ms best %9.1f median  refs/tris %.4f  "
                "interior %u leaves %u depth %u\n",
                scene.name.c_str(), kSplitNames[s], st.sah_cost,
                *std::min_element(ms[s].begin(), ms[s].end()), median(ms[s]),
                static_cast<double>(st.references) / std::max(1u, st.triangles),
                st.interior_nodes, st.leaves, st.max_depth);
  }
  return bvhs;
}

bool same_answers(const std::vector<gpu::Hit>& a, const std::vector<gpu::Hit>& b, QueryKind query) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (query == QueryKind::kAny
            ? (a[i].prim >= 0) != (b[i].prim >= 0)
            : a[i].prim != b[i].prim || a[i].t != b[i].t || a[i].u != b[i].u || a[i].v != b[i].v)
      return false;
  }
  return true;
}

int run_scene(VulkanContext& ctx, const std::string& name, const Options& o) {
  const Scene scene = load_scene(name);
  const std::vector<Bvh> bvhs = build_both(scene, o);
  std::vector<GpuBvh> layouts;
  std::vector<std::unique_ptr<GpuTracer>> tracers;
  for (const Bvh& b : bvhs) {
    layouts.push_back(make_gpu_layout(b, scene));
    tracers.push_back(std::make_unique<GpuTracer>(ctx, layouts.back()));
    tracers.back()->warm_up();
  }
  RayBatchConfig bc;
  bc.secondary_count = o.rays;
  const RayBatches b = make_ray_batches(scene, layouts[0], bc);
  int failures = 0;
  for (const std::string& kind : o.kinds) {
    const RayKind k = *ray_kind_named(kind);  // --kinds lets only kinds through
    const QueryKind query = query_kind(k);
    const std::span<const gpu::Ray> batch = rays_of_kind(b, k);
    std::vector<std::vector<double>> ms(2);
    std::vector<gpu::Hit> answers[2];
    for (int round = 0; round < o.repeat; ++round)
      for (int s = 0; s < 2; ++s) {
        GpuTraceResult r = tracers[s]->trace(batch, query);
        ms[s].push_back(r.kernel_ms);
        if (round == 0) answers[s] = std::move(r.hits);
      }
    if (!same_answers(answers[0], answers[1], query)) {
      std::fprintf(stderr, "%s %s: SBVH answers differ from the object BVH's\n", name.c_str(),
                   kind.c_str());
      ++failures;
    }
    const double base = median(ms[0]);
    for (int s = 0; s < 2; ++s) {
      const double t = median(ms[s]);
      std::printf("%-12s trace %-8s %-8s %9.2f ms %8.2f Mrays/s  %.3fx\n", scene.name.c_str(),
                  kind.c_str(), kSplitNames[s], t,
                  t > 0 ? static_cast<double>(batch.size()) / (t * 1e3) : 0.0,
                  t > 0 ? base / t : 0.0);
    }
  }
  return failures;
}

}  // namespace
}  // namespace hrpp

int main(int argc, char** argv) {
  hrpp::Options o;
  hrpp::VulkanOptions vk;
  CLI::App app{"Spatial splits: object-split BVH against SBVH (build and trace)"};
  app.add_option("scenes", o.scenes, "Scenes (names in scenes/, files)")->capture_default_str();
  app.add_option("--rays", o.rays, "Rays per AO / diffuse batch (primary: 1024x1024)")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 22));
  app.add_option("--repeat", o.repeat, "Interleaved trace rounds; medians are printed")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  app.add_option("--build-repeat", o.build_repeat, "Interleaved build rounds")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  app.add_option("--threads", o.threads, "Build threads (0: all)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  hrpp::bench::add_kinds_option(app, o.kinds);
  app.add_option("--device", vk.device, "Vulkan device (index or name substring)");
  CLI11_PARSE(app, argc, argv);
  try {
    hrpp::VulkanContext ctx(vk);
    std::printf("device %s; build threads %d; trace ratio: object time / this time, > 1 is "
                "faster\n", ctx.info().name.c_str(), o.threads);
    int failures = 0;
    for (const std::string& s : o.scenes) failures += hrpp::run_scene(ctx, s, o);
    return failures == 0 ? 0 : 1;
  } catch (const hrpp::Error& e) {
    std::fprintf(stderr, "bench_sbvh: %s\n", e.what());
    return 1;
  }
}
