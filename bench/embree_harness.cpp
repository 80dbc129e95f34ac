// An independent check of `hrpp bench`'s Embree figures: Embree (3 or 4) driven directly from
// the files of docs/FORMATS.md, sharing no code with hrpp but the API adapter (no scene loader,
// no BVH, no host/reference/embree_tracer). It reads a triangle dump (`hrpp scene
// --dump-triangles`) and a ray file (`hrpp bench --save-rays`), builds the scene as Embree's users build for
// correctness-sensitive work (RTC_BUILD_QUALITY_HIGH, RTC_SCENE_FLAG_ROBUST), traces every ray
// with rtcIntersect1 / rtcOccluded1 on N threads pulling blocks of rays, and prints the median
// wall time, Mrays/s and what it found. `--gpu-ms` (the device time `hrpp trace --repeat 5`
// reports on the same file) adds the GPU/Embree ratio. Not a test.
//   bench_embree_harness --triangles T --rays R [--any-hit] [--threads N] [--repeat K]
//                        [--gpu-ms MS]
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include "reference/embree_api.h"

namespace {

struct RayRecord {  // 32 bytes: docs/FORMATS.md "Rays"
  float ox, oy, oz, tmin, dx, dy, dz, tmax;
};

template <class T>
std::vector<T> read_records(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(std::string("cannot open ") + what + " file " + path);
  const std::vector<char> bytes{std::istreambuf_iterator<char>(in), {}};
  if (bytes.size() % sizeof(T) != 0)
    throw std::runtime_error(path + ": " + std::to_string(bytes.size()) + " bytes is not a whole " +
                             "number of " + std::to_string(sizeof(T)) + "-byte " + what + " records");
  std::vector<T> out(bytes.size() / sizeof(T));
  std::copy(bytes.begin(), bytes.end(), reinterpret_cast<char*>(out.data()));
  return out;
}

// The triangle dump's 9 floats per triangle are already 3 vertices per triangle: Embree reads
// them in place (`vertices` padded for its 16-byte loads), with index triple i = (3i, 3i+1,
// 3i+2).
RTCScene build_scene(RTCDevice device, std::vector<float>& vertices, std::size_t tris) {
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices.data(), 0,
                             3 * sizeof(float), 3 * tris);
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tris));
  for (unsigned i = 0; i < 3 * tris; ++i) idx[i] = i;
  rtcCommitGeometry(g);
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE) throw std::runtime_error("Embree build failed");
  return scene;
}

RTCRay embree_ray(const RayRecord& r) {
  RTCRay e{};
  e.org_x = r.ox, e.org_y = r.oy, e.org_z = r.oz, e.tnear = r.tmin;
  e.dir_x = r.dx, e.dir_y = r.dy, e.dir_z = r.dz, e.tfar = r.tmax;
  e.mask = ~0u;
  return e;
}

// One pass over the rays on `threads` threads; returns the rays that hit (any hit: occluded).
std::uint64_t trace_all(RTCScene scene, const std::vector<RayRecord>& rays, bool any_hit,
                        unsigned threads) {
  constexpr std::size_t kBlock = 1024;
  std::atomic<std::size_t> next{0};
  std::atomic<std::uint64_t> hits{0};
  const auto worker = [&] {
    std::uint64_t mine = 0;
    for (std::size_t b; (b = next.fetch_add(kBlock)) < rays.size();) {
      for (std::size_t i = b; i < std::min(b + kBlock, rays.size()); ++i) {
        if (any_hit) {
          RTCRay r = embree_ray(rays[i]);
          hrpp::embree::occluded1(scene, r);
          mine += r.tfar == -std::numeric_limits<float>::infinity();
        } else {
          RTCRayHit rh{};
          rh.ray = embree_ray(rays[i]);
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          hrpp::embree::intersect1(scene, rh);
          mine += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
      }
    }
    hits += mine;
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  return hits;
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::string triangles_path, rays_path;
  bool any_hit = false;
  unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  int repeat = 5;
  double gpu_ms = 0.0;
  CLI::App app{"Embree on a triangle dump and a ray file: an independent check of hrpp bench"};
  app.add_option("--triangles", triangles_path, "Triangle dump (9 float32 per triangle)")
      ->required();
  app.add_option("--rays", rays_path, "Ray file (32-byte records)")->required();
  app.add_flag("--any-hit", any_hit, "Occlusion queries (rtcOccluded1)");
  app.add_option("--threads", threads, "Threads (default: all)")->check(CLI::Range(1u, 1024u));
  app.add_option("--repeat", repeat, "Timed passes after a warm-up; the median counts")
      ->check(CLI::Range(1, 1000));
  app.add_option("--gpu-ms", gpu_ms, "Device time of the same rays, to print GPU/Embree");
  CLI11_PARSE(app, argc, argv);
  try {
    std::vector<float> vertices = read_records<float>(triangles_path, "triangle");
    if (vertices.size() % 9 != 0)
      throw std::runtime_error(triangles_path + ": not a whole number of 36-byte triangles");
    const std::size_t tris = vertices.size() / 9;
    vertices.resize(vertices.size() + 4);
    const std::vector<RayRecord> rays = read_records<RayRecord>(rays_path, "ray");
    RTCDevice device = rtcNewDevice(("threads=" + std::to_string(threads)).c_str());
    if (!device) throw std::runtime_error("rtcNewDevice failed");
    auto t0 = std::chrono::steady_clock::now();
    RTCScene scene = build_scene(device, vertices, tris);
    std::printf("build       %zu triangles, %.1f ms (high quality, robust), %u threads\n", tris,
                ms_since(t0), threads);
    std::uint64_t hits = trace_all(scene, rays, any_hit, threads);  // warm-up
    std::vector<double> ms;
    for (int k = 0; k < repeat; ++k) {
      t0 = std::chrono::steady_clock::now();
      hits = trace_all(scene, rays, any_hit, threads);
      ms.push_back(ms_since(t0));
    }
    std::sort(ms.begin(), ms.end());
    const double median = ms[ms.size() / 2];
    const double mrays = static_cast<double>(rays.size()) / (median * 1e3);
    std::printf("trace       %zu %s rays, median %.2f ms of %d (%.2f .. %.2f): %.2f Mrays/s, "
                "%llu %s\n",
                rays.size(), any_hit ? "any-hit" : "closest-hit", median, repeat, ms.front(),
                ms.back(), mrays, static_cast<unsigned long long>(hits),
                any_hit ? "occluded" : "hit");
    if (gpu_ms > 0.0) std::printf("gpu/embree  %.3f\n", median / gpu_ms);
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_embree_harness: %s\n", e.what());
    return 1;
  }
  return 0;
}
