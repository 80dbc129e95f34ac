#include "gpu/gpu_tracer.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <string>

#include "common/error.h"
#include "vk/compute_pipeline.h"
#include "kernels/device_bvh.h"
#include "vk/embedded_shaders.h"
#include "kernels/kernel_bindings.h"
#include "gpu/resident_rays.h"
#include "vk/memory_plan.h"
#include "vk/texel_view.h"
#include "vk/vulkan_context.h"
#include "trace/slab_test.h"
#include "trace_interface.h"

namespace hrpp {

static_assert(sizeof(gpu::TraceCounters) == 64);
static_assert(offsetof(gpu::TraceCounters, wide) == 16);
static_assert(sizeof(gpu::TracePushConstants) == 16);
static_assert(HRPP_STACK_SIZE == 64, "shaders/shared/trace_interface.h and host/bvh/gpu_layout.h");
static_assert(std::bit_cast<std::uint32_t>(kSlabFarScale) == HRPP_SLAB_FAR_SCALE_BITS);
static_assert(std::bit_cast<std::uint32_t>(0x1p-80f) == HRPP_TWO_POW_M80_BITS);
static_assert(std::bit_cast<std::uint32_t>(0x1p80f) == HRPP_TWO_POW_80_BITS);
// shaders/lib/texel_fetch.glsl reads these records as 4 (4, 7), 1, 3 and 2 16-byte texels.
static_assert(sizeof(gpu::BvhNode) == 4 * TexelView::kTexelBytes);
static_assert(sizeof(gpu::WideNode) == 4 * TexelView::kTexelBytes);
static_assert(sizeof(gpu::WideFloatNode) == 7 * TexelView::kTexelBytes);
static_assert(sizeof(gpu::BvhLeaf) == 1 * TexelView::kTexelBytes);
static_assert(sizeof(gpu::Ray) == 2 * TexelView::kTexelBytes);

namespace {

// HRPP_SPEC_NODE_FORMAT's value for `f`.
std::uint32_t spec_value(NodeFormat f) {
  switch (f) {
    case NodeFormat::kBinary: return HRPP_NODES_BINARY;
    case NodeFormat::kWide4: return HRPP_NODES_WIDE;
    case NodeFormat::kWide4Float: return HRPP_NODES_WIDE_FLOAT;
  }
  return HRPP_NODES_BINARY;
}

// Before anything is allocated: the tracer's buffers against the device (vk/memory_plan.h).
void check_tracer_fits(const VulkanContext& ctx, const GpuBvh& bvh) {
  check_fits("the BVH of " + std::to_string(bvh.triangles.size()) + " triangles",
             GpuTracer::buffer_needs(bvh, 0), memory_limits(ctx.info()));
}

}  // namespace

std::vector<BufferNeed> GpuTracer::buffer_needs(const GpuBvh& bvh, std::size_t resident_rays) {
  std::vector<BufferNeed> needs = DeviceBvh::buffer_needs(bvh);
  for (BufferNeed& n : ResidentRays::needs(resident_rays)) needs.push_back(std::move(n));
  return needs;
}

GpuTracer::GpuTracer(VulkanContext& ctx, const GpuBvh& bvh, const GpuTracerConfig& config)
    : GpuTracer(ctx, bvh, config, nullptr) {}

GpuTracer::GpuTracer(VulkanContext& ctx, GpuBvh& bvh, const GpuTracerConfig& config,
                     FreeHostArrays)
    : GpuTracer(ctx, bvh, config, &bvh) {}

// With `release` (the same GpuBvh as `bvh`), each host array is freed once uploaded. The
// kernels: `count_steps` counts the interior loop's subgroup iterations
// (GpuTracerConfig::count_steps), the node format is the BVH's (--bvh-nodes).
GpuTracer::GpuTracer(VulkanContext& ctx, const GpuBvh& bvh, const GpuTracerConfig& config,
                     GpuBvh* release)
    : KernelTracer(ctx, (check_tracer_fits(ctx, bvh), config), bvh.bounds), device_bvh_(ctx, bvh) {
  const std::array spec{
      SpecializationConstant{HRPP_SPEC_COUNT_STEPS, config.count_steps ? 1u : 0u},
      SpecializationConstant{HRPP_SPEC_NODE_FORMAT, spec_value(bvh.format())}};
  for (QueryKind kind : kQueryKinds) {
    QueueTraceKernel k{ComputePipeline(ctx, trace_kernel(kind), embedded_spirv(trace_kernel(kind)),
                                       kTraceBindingTypes, sizeof(gpu::TracePushConstants), spec),
                       HRPP_TRACE_BINDING_RAYS, HRPP_TRACE_BINDING_HITS,
                       HRPP_TRACE_BINDING_COUNTERS};
    ComputePipeline indexed(ctx, trace_kernel(kind), embedded_spirv(trace_indexed_kernel(kind)),
                            kTraceListBindingTypes, sizeof(gpu::TracePushConstants), spec);
    device_bvh_.bind(k.pipeline);
    device_bvh_.bind(indexed);
    set_kernels(kind, "trace counters", std::move(k), std::move(indexed));
  }
  device_bvh_.upload(bvh, release);
}

QueueTraceKernel GpuTracer::queue_kernel(QueryKind kind, bool skip_lists) const {
  const Kernel k = skip_lists ? trace_skipping_kernel(kind) : trace_kernel(kind);
  QueueTraceKernel q{ComputePipeline(context(), k, embedded_spirv(k),
                                     skip_lists ? std::span<const VkDescriptorType>(
                                                      kTraceListBindingTypes)
                                                : std::span<const VkDescriptorType>(
                                                      kTraceBindingTypes),
                                     sizeof(gpu::TracePushConstants)),
                     HRPP_TRACE_BINDING_RAYS, HRPP_TRACE_BINDING_HITS, HRPP_TRACE_BINDING_COUNTERS,
                     skip_lists ? HRPP_TRACE_BINDING_SKIP_NODES : QueueTraceKernel::kNoBinding};
  device_bvh_.bind(q.pipeline);
  return q;
}

}  // namespace hrpp
