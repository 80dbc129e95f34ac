// BVH build benchmark: for each scene, our binned SAH builder (host/bvh/) against Embree's
// robust high-quality build (RTC_SCENE_FLAG_ROBUST, RTC_BUILD_QUALITY_HIGH) over the same
// non-degenerate triangles on the same number of threads, interleaved in one run: one warm-up
// build of each, then --repeat rounds of (ours, Embree). Prints best and median build times, the
// ours/Embree ratio of each, our SAH cost and tree size, with the machine and its load average.
// Not a test: it only reports.
//   bench_bvh_build [SCENE...] [--repeat N] [--threads T] [--bins B] [--max-leaf L] [--no-embree]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "bvh/binned_sah_builder.h"
#include "bvh/bvh_stats.h"
#include "common/task_pool.h"
#include "common/error.h"
#include "scene/load_scene.h"

#ifdef HRPP_HAVE_EMBREE
#include "reference/embree_api.h"
#endif

namespace {

struct Timings {
  std::vector<double> ms;
  void add(double v) { ms.push_back(v); }
  double best() const { return *std::min_element(ms.begin(), ms.end()); }
  double median() const {
    std::vector<double> s = ms;
    std::sort(s.begin(), s.end());
    return s.size() % 2 ? s[s.size() / 2] : 0.5 * (s[s.size() / 2 - 1] + s[s.size() / 2]);
  }
};

std::string load_average() {
  std::ifstream f("/proc/loadavg");
  std::string one, five, fifteen;
  if (!(f >> one >> five >> fifteen)) return "unknown";
  return one + " " + five + " " + fifteen;
}

#ifdef HRPP_HAVE_EMBREE

// Embree's build over the scene's non-degenerate triangles, three unshared vertices each (the
// coordinates our builder sees); one device with `threads` threads, a new scene per build.
class EmbreeBuild {
 public:
  EmbreeBuild(const hrpp::Scene& scene, int threads) {
    const std::string config = "threads=" + std::to_string(threads);
    device_ = rtcNewDevice(config.c_str());
    if (!device_) throw hrpp::Error("Embree: rtcNewDevice failed");
    for (const hrpp::Triangle& t : scene.triangles) {
      if (hrpp::is_degenerate(t)) continue;
      for (const glm::vec3& v : {t.v0, t.v1, t.v2}) vertices_.insert(vertices_.end(), {v.x, v.y, v.z});
    }
    indices_.resize(vertices_.size() / 3);
    for (std::size_t i = 0; i < indices_.size(); ++i) indices_[i] = static_cast<unsigned>(i);
    vertices_.push_back(0.0f);  // Embree reads vertex buffers 16 bytes at a time
  }
  ~EmbreeBuild() { rtcReleaseDevice(device_); }
  EmbreeBuild(const EmbreeBuild&) = delete;
  EmbreeBuild& operator=(const EmbreeBuild&) = delete;

  // Milliseconds of rtcCommitScene (the BVH build) on a fresh scene.
  double build() {
    const std::size_t n = indices_.size() / 3;
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices_.data(),
                               0, 3 * sizeof(float), 3 * n);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices_.data(), 0,
                               3 * sizeof(unsigned), n);
    rtcCommitGeometry(geom);
    RTCScene scene = rtcNewScene(device_);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    const auto start = std::chrono::steady_clock::now();
    rtcCommitScene(scene);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const RTCError error = rtcGetDeviceError(device_);
    rtcReleaseScene(scene);
    if (error != RTC_ERROR_NONE) throw hrpp::Error("Embree: build failed (RTCError " +
                                                   std::to_string(error) + ")");
    return ms;
  }

 private:
  RTCDevice device_ = nullptr;
  std::vector<float> vertices_;
  std::vector<unsigned> indices_;
};

#else

class EmbreeBuild {
 public:
  EmbreeBuild(const hrpp::Scene&, int) { throw hrpp::Error("Embree not available in this build"); }
  double build() { return 0.0; }
};

#endif

struct Options {
  std::vector<std::string> scenes = {"builtin:cornell", "teapot", "bunny", "dragon",
                                     "lamborghini"};
  int repeat = 7;
  bool embree = true;
  hrpp::BvhConfig config;
};

void print_header(const Options& o, int threads) {
  std::printf("machine: %u hardware threads, load average %s\n",
              std::thread::hardware_concurrency(), load_average().c_str());
  std::printf("build threads %d (ours and Embree), %d bins, leaves <= %d, %d interleaved rounds\n",
              threads, o.config.bin_count, o.config.max_leaf_size, o.repeat);
  std::printf("%-15s %9s %8s %5s %8s | %9s %9s | %9s %9s | %6s %6s\n", "scene", "triangles",
              "leaves", "depth", "SAH", "ours best", "median", "Embree", "median", "best", "median");
  std::printf("%-15s %9s %8s %5s %8s | %9s %9s | %9s %9s | %13s\n", "", "", "", "", "", "ms", "ms",
              "best ms", "ms", "ours/Embree");
}

void run_scene(const std::string& name, const Options& o, int threads) {
  const hrpp::Scene scene = hrpp::load_scene(name);
  std::optional<EmbreeBuild> embree;
  if (o.embree) embree.emplace(scene, threads);
  hrpp::build_bvh(scene, o.config);  // warm-up: page the triangles in, start the threads
  if (embree) embree->build();
  Timings ours, theirs;
  hrpp::BvhStats stats;
  for (int i = 0; i < o.repeat; ++i) {
    const hrpp::Bvh bvh = hrpp::build_bvh(scene, o.config);
    ours.add(bvh.build_ms);
    if (i == 0) stats = hrpp::compute_bvh_stats(bvh, o.config);
    if (embree) theirs.add(embree->build());
  }
  std::printf("%-15s %9zu %8u %5u %8.4f | %9.1f %9.1f |", name.c_str(), scene.triangles.size(),
              stats.leaves, stats.max_depth, stats.sah_cost, ours.best(), ours.median());
  if (embree)
    std::printf(" %9.1f %9.1f | %6.2f %6.2f\n", theirs.best(), theirs.median(),
                ours.best() / theirs.best(), ours.median() / theirs.median());
  else
    std::printf(" %9s %9s | %6s %6s\n", "-", "-", "-", "-");
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"BVH build benchmark: our binned SAH builder against Embree's robust HQ build"};
  app.add_option("scenes", o.scenes, "Scenes (as for hrpp scene)")->capture_default_str();
  app.add_option("--repeat", o.repeat, "Timed rounds per scene")->check(CLI::PositiveNumber);
  app.add_option("--threads", o.config.threads, "Build threads, ours and Embree's (0: all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--bins", o.config.bin_count, "SAH bins")->capture_default_str();
  app.add_option("--max-leaf", o.config.max_leaf_size, "Largest leaf")->capture_default_str();
  app.add_flag("!--no-embree", o.embree, "Skip Embree");
  CLI11_PARSE(app, argc, argv);
  const int threads = hrpp::resolve_threads(o.config.threads);
  o.config.threads = threads;

  print_header(o, threads);
  int failures = 0;
  for (const std::string& name : o.scenes) {
    try {
      run_scene(name, o, threads);
    } catch (const hrpp::Error& e) {
      std::printf("%-15s skipped: %s\n", name.c_str(), e.what());
      ++failures;
    }
  }
  std::printf("load average after: %s\n", load_average().c_str());
  return failures == 0 ? 0 : 1;
}
