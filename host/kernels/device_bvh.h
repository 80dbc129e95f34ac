// The BVH's arrays on the device, as the trace kernels and the HRPP stage read them: the node
// array (binary or wide nodes), the leaves, and the triangle records as three planes, texel k of
// record i at index i of plane k (shaders/shared/trace_interface.h), each with the texel view
// the kernels read it through. Move-only.
#pragma once

#include <array>
#include <vector>

#include "bvh/gpu_layout.h"
#include "vk/memory_plan.h"
#include "vk/storage_buffer.h"
#include "vk/texel_view.h"
#include "trace_interface.h"

namespace hrpp {

class ComputePipeline;
class VulkanContext;

class DeviceBvh {
 public:
  // The arrays a DeviceBvh of `bvh` allocates (read through texel views only), for check_fits
  // (vk/memory_plan.h).
  static std::vector<BufferNeed> buffer_needs(const GpuBvh& bvh);

  DeviceBvh() = default;
  // Allocates the arrays for `bvh` (nothing is copied yet: upload).
  DeviceBvh(VulkanContext& ctx, const GpuBvh& bvh);

  // Copies `bvh`'s arrays to the device. With `release` (the same GpuBvh as `bvh`), each host
  // array is freed once the device holds it, before the next is copied: the host holds at most
  // one array twice.
  void upload(const GpuBvh& bvh, GpuBvh* release = nullptr);

  // Binds the arrays at their slots (HRPP_TRACE_BINDING_NODES, _LEAVES, _TRIANGLES + k): a trace
  // kernel's or an HRPP stage kernel's, which share them.
  void bind(ComputePipeline& p) const;

 private:
  StorageBuffer nodes_, leaves_;
  std::array<StorageBuffer, HRPP_TRACE_TRIANGLE_PLANES> triangle_planes_;
  TexelView node_view_, leaf_view_;
  std::array<TexelView, HRPP_TRACE_TRIANGLE_PLANES> triangle_plane_views_;
};

}  // namespace hrpp
