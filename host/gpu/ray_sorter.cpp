#include "gpu/ray_sorter.h"

#include <algorithm>
#include <array>
#include <string>

#include "common/error.h"
#include "vk/compute_pipeline.h"
#include "vk/embedded_shaders.h"
#include "vk/storage_buffer.h"
#include "vk/texel_view.h"
#include "vk/vulkan_context.h"
#include "ray_sort_interface.h"
#include "trace/ray_order.h"

namespace hrpp {

static_assert(sizeof(gpu::RaySortPushConstants) == 64);
static_assert(HRPP_SORT_PASSES * HRPP_SORT_DIGIT_BITS >= HRPP_SORT_KEY_BITS);
static_assert(HRPP_SORT_BINS == 1 << HRPP_SORT_DIGIT_BITS);

namespace {

constexpr auto kSortBindingTypes = [] {
  std::array<VkDescriptorType, HRPP_SORT_BINDING_COUNT> t{};
  t.fill(VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  t[HRPP_SORT_BINDING_RAYS] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  t[HRPP_SORT_BINDING_SORTED_RAYS] = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
  return t;
}();

constexpr std::size_t kDoneWords = HRPP_SORT_PASSES + 1;

std::uint32_t groups(std::uint32_t items, std::uint32_t per_group) {
  return (items + per_group - 1) / per_group;
}

// The order array: one uint per ray, whole 16-byte texels (the trace kernels' texel view).
std::size_t order_bytes(std::size_t rays) {
  constexpr std::size_t kPerTexel = TexelView::kTexelBytes / sizeof(std::uint32_t);
  return (rays + kPerTexel - 1) / kPerTexel * TexelView::kTexelBytes;
}

}  // namespace

struct RaySorter::State {
  VulkanContext& ctx;
  RaySortGrid grid;
  std::size_t max_rays;
  StorageBuffer items, counts, order;
  TexelView order_view;  // how the indexed trace kernels read `order`
  ComputePipeline keys, count, scan, scatter, gather;
  // sort(): the host's rays and their sorted copy, grown on demand.
  StorageBuffer host_rays, host_sorted;
  TexelView host_ray_view, host_sorted_view;
  KernelTimer timer;
  bool gathered = false;  // the last sort recorded the gather

  State(VulkanContext& c, const Aabb& bounds, std::size_t max)
      : ctx(c),
        grid(ray_sort_grid(bounds)),
        max_rays((check_max(max), std::max<std::size_t>(max, 1))),
        items(c, 2 * max_rays * 2 * sizeof(std::uint32_t), "ray sort items"),
        counts(c,
               (kDoneWords + std::size_t{HRPP_SORT_BINS} * HRPP_SORT_MAX_BLOCKS) *
                   sizeof(std::uint32_t),
               "ray sort counts"),
        order(c, order_bytes(max_rays), "ray sort order"),
        order_view(c, order),
        keys(pipeline(c, Kernel::ray_sort_keys)),
        count(pipeline(c, Kernel::ray_sort_count)),
        scan(pipeline(c, Kernel::ray_sort_scan)),
        scatter(pipeline(c, Kernel::ray_sort_scatter)),
        gather(pipeline(c, Kernel::ray_sort_gather)),
        timer(c, 2 + 3 * HRPP_SORT_PASSES) {
    for (ComputePipeline* p : all()) {
      p->bind(HRPP_SORT_BINDING_ITEMS, items);
      p->bind(HRPP_SORT_BINDING_COUNTS, counts);
      p->bind(HRPP_SORT_BINDING_ORDER, order);
    }
  }

  static void check_max(std::size_t max) {
    if (max > RaySorter::kMaxRays)
      throw Error("ray sort: " + std::to_string(max) + " rays exceed the " +
                  std::to_string(RaySorter::kMaxRays) + " one sort takes");
  }

  static ComputePipeline pipeline(VulkanContext& c, Kernel kernel) {
    return ComputePipeline(c, kernel, embedded_spirv(kernel), kSortBindingTypes,
                           sizeof(gpu::RaySortPushConstants));
  }

  std::array<ComputePipeline*, 5> all() { return {&keys, &count, &scan, &scatter, &gather}; }

  gpu::RaySortPushConstants push_constants(std::uint32_t n) const {
    gpu::RaySortPushConstants pc{};
    pc.lo = glm::vec4(grid.lo, 0.0f);
    pc.scale = glm::vec4(grid.scale, 0.0f);
    pc.count = n;
    // Enough items per block that blocks stay <= HRPP_SORT_MAX_BLOCKS: the scan's loops then
    // run at most 2 × HRPP_SORT_BINS × HRPP_SORT_MAX_BLOCKS / HRPP_SORT_SCAN_WORKGROUP_SIZE
    // iterations, and a block's at most 2 × HRPP_SORT_BINS + kMaxRays / HRPP_SORT_MAX_BLOCKS.
    pc.block_items = std::max<std::uint32_t>(HRPP_SORT_MIN_BLOCK_ITEMS,
                                             groups(n, HRPP_SORT_MAX_BLOCKS));
    pc.blocks = groups(n, pc.block_items);
    return pc;
  }

  // Keys, then the radix passes; the last one writes `order`.
  void record(VkCommandBuffer cmd, std::uint32_t n, KernelTimer* t) {
    gathered = false;
    if (n > max_rays)
      throw Error("ray sort: " + std::to_string(n) + " rays exceed the sorter's " +
                  std::to_string(max_rays));
    const std::array<std::uint32_t, kDoneWords> zero{};
    record_update(cmd, counts, 0, sizeof zero, zero.data());
    transfer_compute_barrier(cmd);
    if (n == 0) return;
    gpu::RaySortPushConstants pc = push_constants(n);
    const std::uint32_t half = static_cast<std::uint32_t>(max_rays);
    pc.dst = 0;
    record_dispatch(cmd, keys, &pc, groups(n, HRPP_SORT_WORKGROUP_SIZE), t);
    for (std::uint32_t pass = 0; pass < HRPP_SORT_PASSES; ++pass) {
      pc.shift = pass * HRPP_SORT_DIGIT_BITS;
      pc.src = (pass % 2) * half;
      pc.dst = ((pass + 1) % 2) * half;
      const std::uint32_t block_groups = groups(pc.blocks, HRPP_SORT_WORKGROUP_SIZE);
      record_dispatch(cmd, count, &pc, block_groups, t);
      record_dispatch(cmd, scan, &pc, 1, t);
      record_dispatch(cmd, scatter, &pc, block_groups, t);
    }
  }

  // After record(): every ray to its sorted place in the array bound at SORTED_RAYS.
  void record_gather(VkCommandBuffer cmd, std::uint32_t n, KernelTimer* t) {
    gathered = true;
    if (n == 0) return;
    const gpu::RaySortPushConstants pc = push_constants(n);
    record_dispatch(cmd, gather, &pc, groups(n, HRPP_SORT_WORKGROUP_SIZE), t);
  }

  void finish(std::uint32_t n) const {
    std::array<std::uint32_t, kDoneWords> done{};
    counts.download(done.data(), sizeof done);
    for (std::size_t k = 0; k < kDoneWords; ++k)
      if (done[k] != n && (k < HRPP_SORT_PASSES || gathered))
        throw Error(std::string(k < HRPP_SORT_PASSES ? "ray_sort_scatter" : "ray_sort_gather") +
                    ": placed " + std::to_string(done[k]) + " of " + std::to_string(n) +
                    " rays: the driver's loop limiter or a lost dispatch");
  }

  std::vector<std::uint32_t> read_order(std::uint32_t n) const {
    std::vector<std::uint32_t> out(n);
    if (n > 0) order.download(out.data(), out.size() * sizeof(std::uint32_t));
    return out;
  }
};

RaySorter::RaySorter(VulkanContext& ctx, const Aabb& bounds, std::size_t max_rays)
    : s_(std::make_unique<State>(ctx, bounds, max_rays)) {}

RaySorter::~RaySorter() = default;

void RaySorter::bind_rays(const TexelView& rays) {
  for (ComputePipeline* p : s_->all()) p->bind(HRPP_SORT_BINDING_RAYS, rays);
}

void RaySorter::record(VkCommandBuffer cmd, std::uint32_t count, KernelTimer* timer) {
  s_->record(cmd, count, timer);
}

const TexelView& RaySorter::order_view() const { return s_->order_view; }

void RaySorter::finish(std::uint32_t count) const { s_->finish(count); }

std::vector<std::uint32_t> RaySorter::order(std::uint32_t count) const {
  return s_->read_order(count);
}

RaySortResult RaySorter::sort(std::span<const gpu::Ray> rays) {
  const auto n = static_cast<std::uint32_t>(rays.size());
  RaySortResult out;
  if (n == 0) return out;
  State& s = *s_;
  if (s.host_rays.size() < rays.size_bytes()) {
    s.host_ray_view = TexelView();
    s.host_sorted_view = TexelView();
    s.host_rays = StorageBuffer();
    s.host_sorted = StorageBuffer();
    s.host_rays = StorageBuffer(s.ctx, rays.size_bytes(), "rays to sort");
    s.host_sorted = StorageBuffer(s.ctx, rays.size_bytes(), "sorted rays");
    s.host_ray_view = TexelView(s.ctx, s.host_rays);
    s.host_sorted_view = TexelView(s.ctx, s.host_sorted);
  }
  bind_rays(s.host_ray_view);
  s.gather.bind(HRPP_SORT_BINDING_SORTED_RAYS, s.host_sorted_view);
  s.host_rays.upload(rays);
  s.ctx.submit_and_wait(
      [&](VkCommandBuffer cmd) {
        s.timer.reset(cmd);
        s.record(cmd, n, &s.timer);
        s.record_gather(cmd, n, &s.timer);
      },
      "ray sort");
  s.finish(n);
  for (const auto& [kernel, ms] : s.timer.read_ms()) out.kernel_ms += ms;
  out.rays.resize(n);
  s.host_sorted.download(out.rays.data(), rays.size_bytes());
  out.order = s.read_order(n);
  return out;
}

}  // namespace hrpp
