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

int prediction_node(const GpuBvh& bvh, std::uint32_t leaf, std::uint32_t go_up) {
  if (go_up == 0) return leaf_ref(static_cast<int>(leaf));
  int node = bvh.leaves[leaf].parent;
  for (std::uint32_t level = 1; level < go_up; ++level) {
    const int parent = bvh.nodes[static_cast<std::size_t>(node)].link.z;
    if (parent < 0) break;  // the root
    node = parent;
  }
  return node;
}

}  // namespace hrpp
