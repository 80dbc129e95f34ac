#include "trace/ray_order.h"

#include <algorithm>
#include <bit>
#include <utility>

#include "ray_sort_interface.h"

namespace hrpp {
namespace {

// Mirror of ray_sort_cell (shaders/lib/ray_sort_key.glsl).
std::uint32_t ray_sort_cell(float o, float lo, float scale) {
  const float last = static_cast<float>((1u << HRPP_SORT_CELL_BITS) - 1u);
  const float f = (o - lo) * scale;
  return static_cast<std::uint32_t>(f >= 0.0f ? std::min(f, last) : 0.0f);
}

}  // namespace

RaySortGrid ray_sort_grid(const Aabb& bounds) {
  RaySortGrid g;
  if (bounds.empty()) return g;
  g.lo = bounds.lo;
  const float cells = static_cast<float>(1u << HRPP_SORT_CELL_BITS);
  for (int a = 0; a < 3; ++a) {
    const float extent = bounds.hi[a] - bounds.lo[a];
    g.scale[a] = extent > 0.0f ? cells / extent : 0.0f;
  }
  return g;
}

std::uint32_t ray_sort_key(const gpu::Ray& ray, const RaySortGrid& grid) {
  std::uint32_t c[3];
  for (int a = 0; a < 3; ++a) c[a] = ray_sort_cell(ray.origin[a], grid.lo[a], grid.scale[a]);
  std::uint32_t morton = 0;
  for (std::uint32_t b = 0; b < HRPP_SORT_CELL_BITS; ++b)
    morton |= (((c[0] >> b) & 1u) << (3 * b)) | (((c[1] >> b) & 1u) << (3 * b + 1)) |
              (((c[2] >> b) & 1u) << (3 * b + 2));
  std::uint32_t octant = 0;
  for (int a = 0; a < 3; ++a) octant |= (std::bit_cast<std::uint32_t>(ray.dir[a]) >> 31) << a;
  return (octant << (3 * HRPP_SORT_CELL_BITS)) | morton;
}

std::vector<std::uint32_t> stable_ray_order(std::span<const gpu::Ray> rays,
                                            const RaySortGrid& grid) {
  // A counting sort over the whole key: count, exclusive prefix sums, place in input order.
  std::vector<std::uint32_t> keys(rays.size());
  std::vector<std::uint32_t> next(std::size_t{1} << HRPP_SORT_KEY_BITS, 0);
  for (std::size_t i = 0; i < rays.size(); ++i) ++next[keys[i] = ray_sort_key(rays[i], grid)];
  std::uint32_t run = 0;
  for (std::uint32_t& n : next) run += std::exchange(n, run);
  std::vector<std::uint32_t> order(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i)
    order[next[keys[i]]++] = static_cast<std::uint32_t>(i);
  return order;
}

std::vector<gpu::Hit> hits_in_queue_order(std::span<const gpu::Hit> sorted_hits,
                                          std::span<const std::uint32_t> order) {
  std::vector<gpu::Hit> out(sorted_hits.size());
  for (std::size_t j = 0; j < order.size() && j < sorted_hits.size(); ++j)
    out[order[j]] = sorted_hits[j];
  return out;
}

}  // namespace hrpp
