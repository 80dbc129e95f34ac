// Fixed ray batches for speed tests, after Aila and Laine, "Understanding the Efficiency of Ray
// Traversal on GPUs" (HPG 2009): primary, ambient-occlusion and diffuse rays of one view.
// Everything is deterministic from a seed and independent of the thread count: the random
// numbers of ray i are a hash of (seed, kind, i), never a shared generator's stream.
//
//   primary  one ray per pixel of a W×H grid from scene.cameras[0] (aspect W/H unless the camera
//            fixes one), through the pixel centre (default) or a jittered point in the pixel;
//            unit directions, tmin 0, tmax +inf. Closest-hit queries.
//   AO       from the primary hit points, cosine-distributed about the geometric normal turned to
//            face the primary ray, tmax = ao_radius_fraction × the diagonal of the scene's
//            bounds (0.1 by default; Aila–Laine used a scene-dependent AO radius). Any-hit.
//   diffuse  the same origins, cosine-distributed, tmax +inf. Closest-hit.
// Secondary origins are the hit points (from barycentrics) moved off the surface with
// offset_ray_origin() (trace/offset_ray.h, Wächter–Binder); their tmin is 0. Primaries that miss
// spawn nothing: secondary ray i starts at the (i mod H)-th primary hit (H hits in pixel order),
// so a batch always has the requested count unless no primary hits at all (then it is empty).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "bvh/gpu_layout.h"
#include "gpu_types.h"
#include "scene/scene.h"
#include "trace/query_kind.h"

namespace hrpp {

enum class RayKind { kPrimary, kAo, kDiffuse };
const char* ray_kind_name(RayKind kind);  // "primary", "ao", "diffuse"
// The query of a batch kind: closest hit (primary, diffuse) or any hit (AO).
inline QueryKind query_kind(RayKind kind) {
  return kind == RayKind::kAo ? QueryKind::kAny : QueryKind::kClosest;
}
// The kind ray_kind_name() calls `name`, if any.
std::optional<RayKind> ray_kind_named(std::string_view name);

struct RayBatchConfig {
  std::uint32_t width = 1024;         // primary grid: width × height rays
  std::uint32_t height = 1024;
  std::size_t secondary_count = std::size_t{1} << 20;  // rays per AO / diffuse batch
  std::uint64_t seed = 1;
  bool jitter = false;                // false: pixel centres; true: uniform in the pixel
  float ao_radius_fraction = 0.1f;    // AO tmax = this × scene diagonal
  int threads = 0;                    // primary tracing threads; 0: hardware_concurrency()
};

// Secondary rays and, parallel to them, the triangle id each one leaves.
struct SecondaryRays {
  std::vector<gpu::Ray> rays;
  std::vector<int> source_prim;
};

struct RayBatches {
  std::vector<gpu::Ray> primary;
  std::vector<gpu::Hit> primary_hits;  // CPU reference closest hits of `primary`
  std::size_t primary_hit_count = 0;
  SecondaryRays ao;
  SecondaryRays diffuse;
  float ao_tmax = 0.0f;
  float scene_diagonal = 0.0f;         // of bvh.bounds
};

// Camera rays through a width × height grid, row-major from the top-left pixel.
std::vector<gpu::Ray> make_primary_rays(const Camera& camera, std::uint32_t width,
                                        std::uint32_t height, bool jitter, std::uint64_t seed);

// `count` AO or diffuse rays (kind != kPrimary) from the hits of `primaries`; tmax for AO rays
// is ao_tmax (ignored for diffuse). Empty when no primary hit.
SecondaryRays make_secondary_rays(const Scene& scene, std::span<const gpu::Ray> primaries,
                                  std::span<const gpu::Hit> hits, RayKind kind, std::size_t count,
                                  float ao_tmax, std::uint64_t seed);

// Everything above for one view: primaries, their CPU reference hits (multithreaded), AO and
// diffuse batches.
RayBatches make_ray_batches(const Scene& scene, const GpuBvh& bvh, const RayBatchConfig& config);
// The batch of `kind` in `batches`: its primary, AO or diffuse rays.
std::span<const gpu::Ray> rays_of_kind(const RayBatches& batches, RayKind kind);

// Rays per task of the CPU tracers' parallel work (parallel_ranges, hrpp/inline_predictor.h).
inline constexpr std::size_t kRayChunk = 4096;

// Runs body(begin, end) over [0, n) in chunks on a TaskPool of resolve_threads(threads) threads
// (common/task_pool.h), chunks handed out dynamically; rethrows the first exception of a worker.
void parallel_ranges(std::size_t n, int threads,
                     const std::function<void(std::size_t, std::size_t)>& body,
                     std::size_t chunk = kRayChunk);

// The CPU reference (trace/cpu_traversal.h) over a batch on `threads` threads. Any-hit results
// use the hits format: prim 0 occluded, -1 free, t = u = v = 0.
// The same into `hits` (one per ray), which the caller allocated (benchmarks time the trace
// alone).
void trace_batch_cpu(const GpuBvh& bvh, std::span<const gpu::Ray> rays, QueryKind kind,
                     std::span<gpu::Hit> hits, int threads = 0);
std::vector<gpu::Hit> trace_batch_cpu(const GpuBvh& bvh, std::span<const gpu::Ray> rays,
                                      QueryKind kind, int threads = 0);

}  // namespace hrpp
