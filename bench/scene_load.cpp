// Scene loading by format: each file loaded from its bytes to the scene's triangles (no BVH) in
// a process of its own, so that each has its own peak memory; the files interleaved round by
// round; the median of each figure and its ratio to the first file's. A benchmark, not a test.
//   bench_scene_load [--rounds N] FILE [FILE...]   (FILE: any scene hrpp loads)
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/peak_rss.h"
#include "scene/load_scene.h"

namespace {

struct Load {
  double ms = 0.0;
  double peak_mib = 0.0;
  std::size_t triangles = 0;
};

// The child: one load, its figures on stdout.
int load_once(const std::string& file) {
  const auto t0 = std::chrono::steady_clock::now();
  const hrpp::Scene s = hrpp::load_scene(file);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%.3f %.3f %zu\n", ms, static_cast<double>(hrpp::peak_rss_bytes()) / (1 << 20),
              s.triangles.size());
  return 0;
}

Load run_child(const std::string& self, const std::string& file) {
  const std::string cmd = "'" + self + "' --one '" + file + "' 2>/dev/null";
  FILE* p = popen(cmd.c_str(), "r");
  Load l;
  if (p == nullptr || std::fscanf(p, "%lf %lf %zu", &l.ms, &l.peak_mib, &l.triangles) != 3) {
    if (p) pclose(p);
    throw hrpp::Error(file + ": the loading process failed");
  }
  pclose(p);
  return l;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Scene loading by format: time and peak memory, each load a process of its own");
  std::vector<std::string> files;
  std::string one;
  int rounds = 5;
  app.add_option("files", files, "scenes to load (the first is the baseline of the ratios)");
  app.add_option("--rounds", rounds, "interleaved rounds (default 5)")->check(CLI::Range(1, 1000));
  app.add_option("--one", one, "load this file once and print ms, peak MiB, triangles");
  CLI11_PARSE(app, argc, argv);
  try {
    if (!one.empty()) return load_once(one);
    if (files.empty()) throw hrpp::Error("give at least one scene file");
    const std::string self = "/proc/self/exe";
    char path[4096];
    const ssize_t n = readlink(self.c_str(), path, sizeof(path) - 1);
    const std::string exe = n > 0 ? std::string(path, static_cast<std::size_t>(n)) : argv[0];
    std::vector<std::vector<Load>> loads(files.size());
    for (int r = 0; r < rounds; ++r) {
      for (std::size_t f = 0; f < files.size(); ++f) loads[f].push_back(run_child(exe, files[f]));
    }
    std::printf("%d interleaved rounds; medians (min..max), ratios to %s\n", rounds,
                files[0].c_str());
    std::printf("%-40s %10s %16s %9s %12s %9s\n", "file", "triangles", "load ms", "ratio",
                "peak MiB", "ratio");
    double base_ms = 0, base_mib = 0;
    for (std::size_t f = 0; f < files.size(); ++f) {
      std::vector<double> ms, mib;
      for (const Load& l : loads[f]) {
        ms.push_back(l.ms);
        mib.push_back(l.peak_mib);
      }
      const double m = median(ms), p = median(mib);
      if (f == 0) base_ms = m, base_mib = p;
      std::printf("%-40s %10zu %7.0f (%.0f..%.0f) %9.2f %12.1f %9.2f\n", files[f].c_str(),
                  loads[f][0].triangles, m, *std::min_element(ms.begin(), ms.end()),
                  *std::max_element(ms.begin(), ms.end()), m / base_ms, p, p / base_mib);
    }
  } catch (const hrpp::Error& e) {
    std::fprintf(stderr, "bench_scene_load: %s\n", e.what());
    return 1;
  }
  return 0;
}
