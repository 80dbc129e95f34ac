// Ray reordering on the GPU (Garanzha & Loop 2010, Meister et al. 2020): a stable LSD
// radix sort of a queue of rays by ray_sort_key (host/trace/ray_order.h: direction octant, then
// the Morton code of the origin's cell). Its result is the order, a ray index list on the device
// (order_view()) that the indexed trace kernels read (GpuTracer::record with ray indices): no
// ray, hit or path state is moved. sort() also gathers the rays into their sorted places (the
// first version of --reorder, kept for bench_ray_order). Kernels:
// shaders/ray_sort_{keys,count,scan,scatter,gather}.comp; the order equals stable_ray_order()
// exactly.
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

  // The rays record() reads, in queue order (2 texels per ray).
  void bind_rays(const TexelView& rays);
  // Records the sort of the first `count` rays into `cmd`: keys, then the radix passes, whose
  // last writes the order. Dispatches are timed under their kernels when `timer` is given
  // (reported together as "ray_sort": vk/timer_label.h).
  void record(VkCommandBuffer cmd, std::uint32_t count, KernelTimer* timer);
  // The order once a recorded sort has run: entry j (uint, 4 per 16-byte texel) is the queue
  // index of the ray at sorted position j. Valid until the next sort.
  const TexelView& order_view() const;
  // After the submit: throws hrpp::Error unless every pass (and the gather, when sort() ran
  // one) placed all `count` items.
  void finish(std::uint32_t count) const;
  // After the submit: order[j] = the queue index of the ray now at position j.
  std::vector<std::uint32_t> order(std::uint32_t count) const;

  // Uploads `rays`, sorts them on the device, gathers them into sorted order (one submit) and
  // reads back the sorted rays and the order.
  RaySortResult sort(std::span<const gpu::Ray> rays);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace hrpp
