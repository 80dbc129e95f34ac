#include "kernels/device_bvh.h"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <string>

#include "common/free_array.h"
#include "vk/compute_pipeline.h"

namespace hrpp {

static_assert(sizeof(gpu::TriangleRecord) == HRPP_TRACE_TRIANGLE_PLANES * TexelView::kTexelBytes);

namespace {

using Texel = std::array<std::byte, TexelView::kTexelBytes>;

std::string plane_name(int k) { return "BVH triangle plane " + std::to_string(k); }

// Texel `plane` of every record into `buffer`, through a bounded scratch array.
void upload_plane(StorageBuffer& buffer, std::span<const gpu::TriangleRecord> records, int plane) {
  constexpr std::size_t kChunk = std::size_t{1} << 20;  // records per copy (16 MiB of texels)
  std::vector<Texel> texels(std::min(kChunk, records.size()));
  for (std::size_t first = 0; first < records.size(); first += kChunk) {
    const std::size_t n = std::min(kChunk, records.size() - first);
    for (std::size_t i = 0; i < n; ++i)
      std::memcpy(
          texels[i].data(),
          reinterpret_cast<const std::byte*>(&records[first + i]) + plane * TexelView::kTexelBytes,
          TexelView::kTexelBytes);
    buffer.upload(texels.data(), n * sizeof(Texel), first * sizeof(Texel));
  }
}

}  // namespace

std::vector<BufferNeed> DeviceBvh::buffer_needs(const GpuBvh& bvh) {
  constexpr BufferBinding kTexel = BufferBinding::kTexelOnly;
  std::vector<BufferNeed> needs{
      {"BVH node array", bvh.traced_nodes().size(), kTexel},
      {"BVH leaf array", bvh.leaves.size() * sizeof(gpu::BvhLeaf), kTexel}};
  for (int k = 0; k < HRPP_TRACE_TRIANGLE_PLANES; ++k)
    needs.push_back({plane_name(k), bvh.triangles.size() * sizeof(Texel), kTexel});
  return needs;
}

DeviceBvh::DeviceBvh(VulkanContext& ctx, const GpuBvh& bvh) {
  const std::vector<BufferNeed> needs = buffer_needs(bvh);
  nodes_ = StorageBuffer(ctx, needs[0]);
  leaves_ = StorageBuffer(ctx, needs[1]);
  node_view_ = TexelView(ctx, nodes_);
  leaf_view_ = TexelView(ctx, leaves_);
  for (int k = 0; k < HRPP_TRACE_TRIANGLE_PLANES; ++k) {
    triangle_planes_[k] = StorageBuffer(ctx, needs[2 + k]);
    triangle_plane_views_[k] = TexelView(ctx, triangle_planes_[k]);
  }
}

void DeviceBvh::upload(const GpuBvh& bvh, GpuBvh* release) {
  nodes_.upload(bvh.traced_nodes().data(), bvh.traced_nodes().size());
  if (release) {
    free_array(release->nodes);
    free_array(release->wide_nodes);
    free_array(release->wide_float_nodes);
  }
  leaves_.upload(std::span<const gpu::BvhLeaf>(bvh.leaves));
  if (release) free_array(release->leaves);
  for (int k = 0; k < HRPP_TRACE_TRIANGLE_PLANES; ++k)
    upload_plane(triangle_planes_[k], bvh.triangles, k);
  if (release) free_array(release->triangles);
}

void DeviceBvh::bind(ComputePipeline& p) const {
  p.bind(HRPP_TRACE_BINDING_NODES, node_view_);
  p.bind(HRPP_TRACE_BINDING_LEAVES, leaf_view_);
  for (int k = 0; k < HRPP_TRACE_TRIANGLE_PLANES; ++k)
    p.bind(HRPP_TRACE_BINDING_TRIANGLES + k, triangle_plane_views_[k]);
}

}  // namespace hrpp
