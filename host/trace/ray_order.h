// Ray reordering on the CPU: the key that groups similar rays (the direction's octant above the
// Morton code of the origin's cell in the scene bounds) and the stable order of a batch by that
// key. The ground truth of the GPU sort (host/gpu/ray_sorter.h, shaders/ray_sort_*.comp), which
// must produce exactly this permutation.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bvh/aabb.h"
#include "common/name_table.h"
#include "gpu_types.h"

namespace hrpp {

// How a queue of rays is ordered before it is traced (--reorder).
enum class RayOrder {
  kOff,     // as produced
  kMorton,  // by ray_sort_key: octant, then the Morton code of the origin's cell
};
inline constexpr NameTable<RayOrder, 2> kRayOrderNames = {
    {{RayOrder::kOff, "off"}, {RayOrder::kMorton, "morton"}}};
constexpr const char* ray_order_name(RayOrder o) { return name_in(kRayOrderNames, o); }

// The grid the key quantizes origins in: cells per unit length on each axis from `lo`.
struct RaySortGrid {
  glm::vec3 lo{0.0f};
  glm::vec3 scale{0.0f};  // 2^HRPP_SORT_CELL_BITS / extent; 0 on an axis the bounds are flat in
};
RaySortGrid ray_sort_grid(const Aabb& bounds);

// Mirror of shaders/lib/ray_sort_key.glsl, operation for operation.
std::uint32_t ray_sort_key(const gpu::Ray& ray, const RaySortGrid& grid);

// The stable order by key: order[j] is the index of the ray that goes to position j.
std::vector<std::uint32_t> stable_ray_order(std::span<const gpu::Ray> rays,
                                            const RaySortGrid& grid);

// The hits of rays traced in sorted order, put back in the queue's order (hit j belongs to ray
// order[j]).
std::vector<gpu::Hit> hits_in_queue_order(std::span<const gpu::Hit> sorted_hits,
                                          std::span<const std::uint32_t> order);

}  // namespace hrpp
