#include "trace/ray_batches.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

#include "common/task_pool.h"
#include "trace/cpu_traversal.h"
#include "trace/offset_ray.h"

namespace hrpp {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kTwoPi = 6.28318530717958648f;

// splitmix64 finaliser (Steele, Lea, Flood 2014): a good 64-bit mix, so the numbers of ray i are
// a pure function of (seed, stream, i).
std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Two uniform floats in [0, 1) for element `index` of stream `stream`.
glm::vec2 uniform2(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  const std::uint64_t h = mix64(mix64(seed ^ (stream << 56)) ^ index);
  const std::uint64_t h2 = mix64(h);
  constexpr float kScale = 1.0f / 16777216.0f;  // 2^-24: 24 random mantissa bits, never 1
  return {static_cast<float>(h >> 40) * kScale, static_cast<float>(h2 >> 40) * kScale};
}

// Orthonormal basis around unit n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
void basis(const glm::vec3& n, glm::vec3& b1, glm::vec3& b2) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  b1 = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
  b2 = {b, sign + n.y * n.y * a, -n.y};
}

// Cosine-distributed unit direction about unit n (Malley's method: uniform disk, projected up).
glm::vec3 cosine_direction(const glm::vec3& n, glm::vec2 u) {
  glm::vec3 b1, b2;
  basis(n, b1, b2);
  const float r = std::sqrt(u.x);
  const float phi = kTwoPi * u.y;
  const float z = std::sqrt(std::max(0.0f, 1.0f - u.x));  // > 0: u.x < 1
  return glm::normalize(r * std::cos(phi) * b1 + r * std::sin(phi) * b2 + z * n);
}

}  // namespace

const char* ray_kind_name(RayKind kind) {
  switch (kind) {
    case RayKind::kPrimary: return "primary";
    case RayKind::kAo: return "ao";
    case RayKind::kDiffuse: return "diffuse";
  }
  return "?";
}

std::optional<RayKind> ray_kind_named(std::string_view name) {
  for (RayKind kind : {RayKind::kPrimary, RayKind::kAo, RayKind::kDiffuse})
    if (name == ray_kind_name(kind)) return kind;
  return std::nullopt;
}

void parallel_ranges(std::size_t n, int threads,
                     const std::function<void(std::size_t, std::size_t)>& body, std::size_t chunk) {
  chunk = std::max<std::size_t>(chunk, 1);
  const std::size_t tasks = chunks(n, chunk);
  TaskPool pool(static_cast<int>(
      std::min<std::size_t>(static_cast<std::size_t>(resolve_threads(threads)), tasks)));
  pool.parallel_for(tasks, [&](std::size_t c, int) {
    body(c * chunk, std::min(n, (c + 1) * chunk));
  });
}

void trace_batch_cpu(const GpuBvh& bvh, std::span<const gpu::Ray> rays, QueryKind kind,
                     std::span<gpu::Hit> hits, int threads) {
  parallel_ranges(rays.size(), threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      hits[i] = kind == QueryKind::kAny
                    ? (trace_any(bvh, rays[i]) ? gpu::Hit{0, 0.0f, 0.0f, 0.0f} : kMiss)
                    : trace_closest(bvh, rays[i]);
  });
}

std::vector<gpu::Hit> trace_batch_cpu(const GpuBvh& bvh, std::span<const gpu::Ray> rays,
                                      QueryKind kind, int threads) {
  std::vector<gpu::Hit> hits(rays.size());
  trace_batch_cpu(bvh, rays, kind, hits, threads);
  return hits;
}

std::vector<gpu::Ray> make_primary_rays(const Camera& camera, std::uint32_t width,
                                        std::uint32_t height, bool jitter, std::uint64_t seed) {
  const glm::vec3 forward = glm::normalize(camera.forward);
  const glm::vec3 right_handed = glm::normalize(glm::cross(forward, camera.up));
  const glm::vec3 up = glm::cross(right_handed, forward);
  const glm::vec3 right = camera.mirrored ? -right_handed : right_handed;
  const float aspect = camera.aspect > 0.0f
                           ? camera.aspect
                           : static_cast<float>(width) / static_cast<float>(std::max(height, 1u));
  const float half_h = std::tan(0.5f * camera.yfov);
  const float half_w = half_h * aspect;
  std::vector<gpu::Ray> rays(static_cast<std::size_t>(width) * height);
  for (std::uint32_t y = 0; y < height; ++y) {
    for (std::uint32_t x = 0; x < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * width + x;
      const glm::vec2 j = jitter ? uniform2(seed, 0, i) : glm::vec2(0.5f);
      const float sx = 2.0f * (static_cast<float>(x) + j.x) / static_cast<float>(width) - 1.0f;
      const float sy = 1.0f - 2.0f * (static_cast<float>(y) + j.y) / static_cast<float>(height);
      rays[i] = {camera.position, 0.0f,
                 glm::normalize(forward + sx * half_w * right + sy * half_h * up), kInf};
    }
  }
  return rays;
}

SecondaryRays make_secondary_rays(const Scene& scene, std::span<const gpu::Ray> primaries,
                                  std::span<const gpu::Hit> hits, RayKind kind, std::size_t count,
                                  float ao_tmax, std::uint64_t seed) {
  SecondaryRays out;
  std::vector<std::size_t> hit_index;
  for (std::size_t i = 0; i < hits.size() && i < primaries.size(); ++i)
    if (hits[i].prim >= 0) hit_index.push_back(i);
  if (hit_index.empty() || kind == RayKind::kPrimary) return out;
  out.rays.resize(count);
  out.source_prim.resize(count);
  const float tmax = kind == RayKind::kAo ? ao_tmax : kInf;
  const std::uint64_t stream = kind == RayKind::kAo ? 1 : 2;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t p = hit_index[i % hit_index.size()];
    const gpu::Hit& h = hits[p];
    const Triangle& tri = scene.triangles[static_cast<std::size_t>(h.prim)];
    const glm::vec3 n = facing_normal(tri, primaries[p].dir);
    const glm::vec3 origin = offset_ray_origin(barycentric_point(tri, h.u, h.v), n);
    out.rays[i] = {origin, 0.0f, cosine_direction(n, uniform2(seed, stream, i)), tmax};
    out.source_prim[i] = h.prim;
  }
  return out;
}

std::span<const gpu::Ray> rays_of_kind(const RayBatches& batches, RayKind kind) {
  switch (kind) {
    case RayKind::kPrimary: return batches.primary;
    case RayKind::kAo: return batches.ao.rays;
    case RayKind::kDiffuse: return batches.diffuse.rays;
  }
  return {};
}

RayBatches make_ray_batches(const Scene& scene, const GpuBvh& bvh, const RayBatchConfig& config) {
  RayBatches b;
  b.primary = make_primary_rays(scene.cameras.at(0), config.width, config.height, config.jitter,
                                config.seed);
  b.primary_hits = trace_batch_cpu(bvh, b.primary, QueryKind::kClosest, config.threads);
  b.primary_hit_count = static_cast<std::size_t>(std::count_if(
      b.primary_hits.begin(), b.primary_hits.end(), [](const gpu::Hit& h) { return h.prim >= 0; }));
  b.scene_diagonal = bvh.bounds.empty() ? 0.0f : glm::length(bvh.bounds.extent());
  b.ao_tmax = config.ao_radius_fraction * b.scene_diagonal;
  b.ao = make_secondary_rays(scene, b.primary, b.primary_hits, RayKind::kAo,
                             config.secondary_count, b.ao_tmax, config.seed);
  b.diffuse = make_secondary_rays(scene, b.primary, b.primary_hits, RayKind::kDiffuse,
                                  config.secondary_count, b.ao_tmax, config.seed);
  return b;
}

}  // namespace hrpp
