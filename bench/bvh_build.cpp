// BVH build benchmark: for each scene, one warm-up build then N timed builds; prints the median
// build time, SAH cost and tree size, with the machine it ran on. Not a test: it only reports.
//   bench_bvh_build [SCENE...] [--repeat N] [--threads T] [--bins B] [--max-leaf L]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "bvh/binned_sah_builder.h"
#include "bvh/bvh_stats.h"
#include "common/error.h"
#include "scene/load_scene.h"

int main(int argc, char** argv) {
  std::vector<std::string> scenes = {"builtin:cornell", "teapot", "bunny", "dragon",
                                     "lamborghini"};
  int repeat = 5;
  hrpp::BvhConfig config;
  CLI::App app{"Binned-SAH BVH build benchmark"};
  app.add_option("scenes", scenes, "Scenes (as for hrpp scene)")->capture_default_str();
  app.add_option("--repeat", repeat, "Timed builds per scene")->check(CLI::PositiveNumber);
  app.add_option("--threads", config.threads, "Build threads (0: all)")->capture_default_str();
  app.add_option("--bins", config.bin_count, "SAH bins")->capture_default_str();
  app.add_option("--max-leaf", config.max_leaf_size, "Largest leaf")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  std::printf("machine: %u hardware threads, build threads %d (0 = all), %d bins, leaves <= %d\n",
              std::thread::hardware_concurrency(), config.threads, config.bin_count,
              config.max_leaf_size);
  std::printf("%-18s %10s %9s %9s %6s %9s %11s %11s %10s\n", "scene", "triangles", "interior",
              "leaves", "depth", "SAH", "build ms", "best ms", "Mtris/s");
  int failures = 0;
  for (const std::string& name : scenes) {
    try {
      const hrpp::Scene scene = hrpp::load_scene(name);
      hrpp::build_bvh(scene, config);  // warm-up: page in the triangles, spin up threads
      std::vector<double> ms;
      hrpp::BvhStats stats;
      for (int i = 0; i < repeat; ++i) {
        const hrpp::Bvh bvh = hrpp::build_bvh(scene, config);
        ms.push_back(bvh.build_ms);
        if (i == 0) stats = hrpp::compute_bvh_stats(bvh, config);
      }
      std::sort(ms.begin(), ms.end());
      const double median = ms[ms.size() / 2];
      std::printf("%-18s %10zu %9u %9u %6u %9.2f %11.1f %11.1f %10.2f\n", name.c_str(),
                  scene.triangles.size(), stats.interior_nodes, stats.leaves, stats.max_depth,
                  stats.sah_cost, median, ms.front(),
                  static_cast<double>(scene.triangles.size()) / (median * 1e3));
    } catch (const hrpp::Error& e) {
      std::printf("%-18s skipped: %s\n", name.c_str(), e.what());
      ++failures;
    }
  }
  return failures == 0 ? 0 : 1;
}
