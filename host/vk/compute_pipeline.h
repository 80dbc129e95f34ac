// A compute pipeline from embedded SPIR-V (specialization constants, push constants) with its
// own descriptor set of storage buffers and uniform texel buffers, and the timestamp pool that times dispatches per kernel
// name. Move-only.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <vulkan/vulkan.h>

#include "vk/timer_label.h"
#include "kernel_names.h"

namespace hrpp {

class VulkanContext;
class StorageBuffer;
class TexelView;

struct SpecializationConstant {
  std::uint32_t id;
  std::uint32_t value;
};

class ComputePipeline {
 public:
  // `kernel`: what its dispatches are timed and named as (the SPIR-V may be a variant of it).
  // `binding_count` storage buffers at bindings 0..binding_count-1 of set 0.
  ComputePipeline(VulkanContext& ctx, Kernel kernel, std::span<const std::uint32_t> spirv,
                  std::uint32_t binding_count, std::uint32_t push_constant_bytes,
                  std::span<const SpecializationConstant> specialization = {});
  // Binding i of set 0 has descriptor type binding_types[i]: VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
  // VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER or VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER (a
  // kernel's vec4 stores: one per lane instead of one per 32-bit word on lavapipe), or
  // VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR (ray queries).
  ComputePipeline(VulkanContext& ctx, Kernel kernel, std::span<const std::uint32_t> spirv,
                  std::span<const VkDescriptorType> binding_types,
                  std::uint32_t push_constant_bytes,
                  std::span<const SpecializationConstant> specialization = {});
  ~ComputePipeline();
  ComputePipeline(ComputePipeline&&) noexcept;
  ComputePipeline& operator=(ComputePipeline&&) noexcept;
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  // Points a binding at a buffer (do not call while a submit using the set is in flight).
  void bind(std::uint32_t binding, const StorageBuffer& buffer);
  // Same for a uniform or storage texel buffer binding.
  void bind(std::uint32_t binding, const TexelView& view);
  // Same for an acceleration structure binding (VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR).
  void bind(std::uint32_t binding, VkAccelerationStructureKHR structure);

  Kernel kernel() const;
  const char* name() const { return kernel_name(kernel()); }
  VkPipeline pipeline() const;
  VkPipelineLayout layout() const;
  VkDescriptorSet descriptor_set() const;
  std::uint32_t push_constant_bytes() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

// Timestamp query pool: dispatches recorded with a timer are timed on the device and summed per
// kernel name. When the queue has no timestamps, times are left at 0 (has_timestamps() false).
class KernelTimer {
 public:
  explicit KernelTimer(VulkanContext& ctx, std::uint32_t max_dispatches = 64);
  ~KernelTimer();
  KernelTimer(KernelTimer&&) noexcept;
  KernelTimer& operator=(KernelTimer&&) noexcept;
  KernelTimer(const KernelTimer&) = delete;
  KernelTimer& operator=(const KernelTimer&) = delete;

  bool has_timestamps() const;
  // Call once at the start of each command buffer that times dispatches.
  void reset(VkCommandBuffer cmd);
  void begin(VkCommandBuffer cmd, const TimerLabel& label);
  void end(VkCommandBuffer cmd);
  // After the submit has finished: milliseconds per label for the dispatches since reset().
  std::map<TimerLabel, double> read_ms() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

// Records push constants + bind + dispatch of `groups` workgroups along x, timed when `timer` is
// given (under `label`, or the pipeline's kernel), then a compute→compute barrier so the next
// dispatch sees this one's writes.
void record_dispatch(VkCommandBuffer cmd, const ComputePipeline& pipeline, const void* push,
                     std::uint32_t groups, KernelTimer* timer,
                     std::optional<TimerLabel> label = std::nullopt);
// The same with the workgroup counts read on the device from a VkDispatchIndirectCommand at
// `offset` in `args` (written by an earlier dispatch: make it visible to
// VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT first, e.g. with indirect_args_barrier).
void record_dispatch_indirect(VkCommandBuffer cmd, const ComputePipeline& pipeline,
                              const void* push, const StorageBuffer& args, VkDeviceSize offset,
                              KernelTimer* timer, std::optional<TimerLabel> label = std::nullopt);
// Makes compute-shader writes visible to indirect dispatches, copies and later dispatches.
void indirect_args_barrier(VkCommandBuffer cmd);
// Writes `bytes` (at most 65536, a multiple of 4) of `data` into `dst` at `offset` (record a
// barrier after).
void record_update(VkCommandBuffer cmd, const StorageBuffer& dst, VkDeviceSize offset,
                   VkDeviceSize bytes, const void* data);
// Copies `bytes` from `src` at `src_offset` to `dst` at `dst_offset` (record a barrier after).
void record_copy(VkCommandBuffer cmd, const StorageBuffer& src, VkDeviceSize src_offset,
                 const StorageBuffer& dst, VkDeviceSize dst_offset, VkDeviceSize bytes);
// Makes transfer (fill, update, copy) and compute-shader writes visible to later transfers,
// dispatches and host reads.
void transfer_compute_barrier(VkCommandBuffer cmd);

}  // namespace hrpp
