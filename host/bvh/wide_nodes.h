// The 4-wide node formats (--bvh-nodes wide4, wide4-float): the binary layout's interior nodes
// collapsed into WideNodes (shaders/shared/gpu_types.h), whose child boxes are quantised to 8
// bits per bound, or WideFloatNodes, which keep them as floats.
// The leaves and triangle records stay the binary layout's, so a trace over either format
// tests the same leaves and answers the same; only the interior steps differ.
#pragma once

#include <vector>

#include "gpu_types.h"

namespace hrpp {

struct GpuBvh;

// One wide node per group of binary nodes: starting from a binary node's two children, the
// interior child with the largest surface area is replaced by its two children until there are
// four or only leaves are left. Nodes are numbered depth-first (the root is 0). A child with an
// empty box holds no triangle and becomes an empty slot.
//
// WideNode: a child's box is rounded outward onto its node's grid (shaders/shared/wide_node.h),
// so it holds the child's exact box whether or not the device flushes subnormal results to
// zero. Throws hrpp::Error when a node's box is too large for the grid (more than about 3.4e38
// wide).
std::vector<gpu::WideNode> make_wide_nodes(const GpuBvh& bvh);
// WideFloatNode: the children's exact boxes.
std::vector<gpu::WideFloatNode> make_wide_float_nodes(const GpuBvh& bvh);

}  // namespace hrpp
