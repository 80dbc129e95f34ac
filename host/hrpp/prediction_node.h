// The node HRPP stores for a ray: the leaf that held its hit, or that leaf's ancestor `go_up`
// levels above (the paper's go-up level). The GPU uses it through a table computed here once:
// the prediction node of every triangle id (GpuPredictor, binding HRPP_STAGE_BINDING_NODE_OF_PRIM).
#pragma once

#include <cstdint>
#include <vector>

#include "bvh/gpu_layout.h"

namespace hrpp {

inline constexpr std::uint32_t kNoLeaf = 0xFFFFFFFFu;

// leaf index of every triangle id (kNoLeaf for ids in no leaf: degenerate triangles), sized to
// the largest id + 1 (at least 1). A triangle in several leaves (spatial splits) gets the first
// of them in leaf order (depth first). The kernels read the same array to find the leaf of a hit.
std::vector<std::uint32_t> leaf_of_prim(const GpuBvh& bvh);

// Child reference (~leaf, or an interior node index) of the ancestor `go_up` levels above leaf
// `leaf`, then further up while that node's box's largest extent is below `size` × the scene
// box's (bvh.bounds) largest extent (a scale-free go-up: a dense mesh's leaves are small, a
// coarse mesh's large); stops at the root.
int prediction_node(const GpuBvh& bvh, std::uint32_t leaf, std::uint32_t go_up, float size = 0.0f);

}  // namespace hrpp
