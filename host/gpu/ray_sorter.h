// Ray reordering on the GPU (issue 12; Garanzha & Loop 2010, Meister et al. 2020): a stable LSD
// radix sort of a queue of rays by ray_sort_key (host/trace/ray_order.h: direction octant, then
// the Morton code of the origin's cell), then a gather that writes every ray, and optionally a
// 32-byte payload per ray (the renderer's path state), to its sorted position. Kernels:
// shaders/ray_sort_{keys,count,scan,scatter,gather}.comp; the permutation equals
// stable_ray_order() exactly.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <vulkan/vulkan.h>

#include "bvh/aabb.h"
#include "gpu_types.h"

namespace hrpp {

class VulkanContext;
class KernelTimer;
class TexelView;

struct RaySortResult {
  std::vector<gpu::Ray> rays;         // sorted
  std::vector<std::uint32_t> order;   // order[j]: the input index of sorted ray j
  double kernel_ms = 0.0;             // device time of the sort's dispatches
};

class RaySorter {
 public:
  // Most rays one sort takes: the item array's two halves fill one storage buffer's range.
  static constexpr std::size_t kMaxRays = std::size_t{1} << 22;

  // Sorts up to `max_rays` rays at once, keys quantized in `bounds` (the scene's). Throws
  // hrpp::Error when max_rays exceeds what one storage buffer holds.
  RaySorter(VulkanContext& ctx, const Aabb& bounds, std::size_t max_rays);
  ~RaySorter();
  RaySorter(const RaySorter&) = delete;
  RaySorter& operator=(const RaySorter&) = delete;

  // The arrays record() reads and writes, as texel views: rays in queue order and where their
  // sorted copies go; with payloads, 2 texels per ray each (nullptr: rays only).
  void bind(const TexelView& rays, const TexelView& sorted_rays, const TexelView* payload,
            const TexelView* sorted_payload);
  // Records the sort of the first `count` rays into `cmd`: keys, the radix passes, the gather.
  // Dispatches are timed under "ray_sort" when `timer` is given.
  void record(VkCommandBuffer cmd, std::uint32_t count, KernelTimer* timer);
  // After the submit: throws hrpp::Error unless every pass placed all `count` items.
  void finish(std::uint32_t count) const;
  // After the submit: order[j] = the queue index of the ray now at position j.
  std::vector<std::uint32_t> order(std::uint32_t count) const;

  // Uploads `rays`, sorts them on the device (one submit) and reads back the sorted rays and the
  // permutation (hrpp trace --reorder).
  RaySortResult sort(std::span<const gpu::Ray> rays);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace hrpp
