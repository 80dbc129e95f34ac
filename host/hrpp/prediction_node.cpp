#include "hrpp/prediction_node.h"

#include <algorithm>

namespace hrpp {

std::vector<std::uint32_t> leaf_of_prim(const GpuBvh& bvh) {
  std::uint32_t max_prim = 0;
  for (const gpu::TriangleRecord& t : bvh.triangles) max_prim = std::max(max_prim, t.prim);
  std::vector<std::uint32_t> out(std::size_t{max_prim} + 1, kNoLeaf);
  for (std::uint32_t l = 0; l < bvh.leaves.size(); ++l) {
    const gpu::BvhLeaf& leaf = bvh.leaves[l];
    for (std::uint32_t i = leaf.first_triangle; i < leaf.first_triangle + leaf.triangle_count; ++i)
      if (out[bvh.triangles[i].prim] == kNoLeaf) out[bvh.triangles[i].prim] = l;
  }
  return out;
}

namespace {

// The largest extent of interior node n's box (the union of its children's boxes).
float node_extent(const gpu::BvhNode& n) {
  const float x = std::max(n.left_xy.y, n.right_xy.y) - std::min(n.left_xy.x, n.right_xy.x);
  const float y = std::max(n.left_xy.w, n.right_xy.w) - std::min(n.left_xy.z, n.right_xy.z);
  const float z = std::max(n.lr_z.y, n.lr_z.w) - std::min(n.lr_z.x, n.lr_z.z);
  return std::max({x, y, z});
}

}  // namespace

int prediction_node(const GpuBvh& bvh, std::uint32_t leaf, std::uint32_t go_up, float size) {
  if (go_up == 0 && size <= 0.0f) return leaf_ref(static_cast<int>(leaf));
  const glm::vec3 e = bvh.bounds.extent();
  const float min_extent = size * std::max({e.x, e.y, e.z});
  int node = bvh.leaves[leaf].parent;
  for (std::uint32_t level = 1;; ++level) {
    const gpu::BvhNode& n = bvh.nodes[static_cast<std::size_t>(node)];
    if (level >= go_up && !(node_extent(n) < min_extent)) break;
    if (n.link.z < 0) break;  // the root
    node = n.link.z;
  }
  return node;
}

}  // namespace hrpp
