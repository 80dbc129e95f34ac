#include "bvh/prim_refs.h"

#include <algorithm>
#include <vector>

#include "scene/load_scene.h"

namespace hrpp::bvh_build {
namespace {

// Triangles per task when making references.
constexpr std::uint32_t kRefChunk = 1u << 14;

// Writes the references of the non-degenerate triangles among tris[begin, end) from out[0] on,
// growing the bounds; returns how many.
std::uint32_t write_references(const std::vector<Triangle>& tris, std::size_t begin,
                               std::size_t end, PrimRef* out, Box4& bounds, Box4& centroids) {
  const simd::Float4 zero = simd::splat3(0.0f);
  PrimRef* r = out;
  for (std::size_t i = begin; i < end; ++i) {
    const Triangle& t = tris[i];
    if (is_degenerate(t)) continue;
    const simd::Float4 a = simd::set3(t.v0.x, t.v0.y, t.v0.z),
                       b = simd::set3(t.v1.x, t.v1.y, t.v1.z),
                       c = simd::set3(t.v2.x, t.v2.y, t.v2.z);
    r->set(simd::min(simd::min(a, b), c) + zero, simd::max(simd::max(a, b), c) + zero,
           static_cast<std::uint32_t>(i));
    bounds.grow(Box4{r->lo4(), r->hi4()});
    centroids.grow(r->centroid());
    ++r;
  }
  return static_cast<std::uint32_t>(r - out);
}

}  // namespace

// The references of the non-degenerate triangles in id order, with their bounds: one pass in
// parallel chunks, each writing from its own start, then the chunks moved down over the gaps
// the degenerate triangles left (none to move in a scene without them).
References make_references(const Scene& scene, TaskPool& pool) {
  const std::vector<Triangle>& tris = scene.triangles;
  const std::size_t tasks = chunks(tris.size(), kRefChunk);
  References out;
  out.refs.reset(new PrimRef[tris.size()]);
  std::vector<std::uint32_t> kept(tasks);
  std::vector<Box4> bounds(pool.size()), centroids(pool.size());
  pool.parallel_for(tasks, [&](std::size_t k, int thread) {
    const std::size_t begin = k * kRefChunk, end = std::min(tris.size(), begin + kRefChunk);
    kept[k] = write_references(tris, begin, end, out.refs.get() + begin, bounds[thread],
                               centroids[thread]);
  });
  for (std::size_t k = 0; k < tasks; ++k) {
    PrimRef* from = out.refs.get() + k * kRefChunk;
    if (out.count != k * kRefChunk) std::copy(from, from + kept[k], out.refs.get() + out.count);
    out.count += kept[k];
  }
  out.degenerate = static_cast<std::uint32_t>(tris.size() - out.count);
  for (int t = 0; t < pool.size(); ++t) {
    out.bounds.grow(bounds[t]);
    out.centroids.grow(centroids[t]);
  }
  return out;
}

}  // namespace hrpp::bvh_build
