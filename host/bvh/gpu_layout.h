// The BVH as the GPU (and the CPU reference traversal) reads it: Aila–Laine 64-byte nodes, leaf
// records and triangle records, as plain arrays ready to upload (shaders/shared/gpu_types.h).
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "bvh/aabb.h"
#include "bvh/bvh.h"
#include "gpu_types.h"
#include "scene/scene.h"

// Deepest traversal stack the kernels and the CPU reference keep (one entry per tree level).
#define HRPP_STACK_SIZE 64

namespace hrpp {

static_assert(sizeof(gpu::BvhNode) == 64);
static_assert(offsetof(gpu::BvhNode, right_xy) == 16 && offsetof(gpu::BvhNode, lr_z) == 32 &&
              offsetof(gpu::BvhNode, link) == 48);
static_assert(sizeof(gpu::BvhLeaf) == 16);
static_assert(sizeof(gpu::TriangleRecord) == 48);
static_assert(offsetof(gpu::TriangleRecord, prim) == 12 && offsetof(gpu::TriangleRecord, v1) == 16 &&
              offsetof(gpu::TriangleRecord, v2) == 32);
static_assert(sizeof(gpu::Ray) == 32 && offsetof(gpu::Ray, dir) == 16 &&
              offsetof(gpu::Ray, tmax) == 28);
static_assert(sizeof(gpu::Hit) == 16);

// A child reference in BvhNode::link: >= 0 interior node, < 0 leaf ~reference.
inline bool is_leaf_ref(int ref) { return ref < 0; }
inline int leaf_index(int ref) { return ~ref; }
inline int leaf_ref(int leaf) { return ~leaf; }

struct GpuBvh {
  std::vector<gpu::BvhNode> nodes;            // nodes[0] is the root, always interior
  std::vector<gpu::BvhLeaf> leaves;
  std::vector<gpu::TriangleRecord> triangles;  // in leaf order
  Aabb bounds;                                  // of the whole scene's tree
  std::size_t bytes() const {
    return nodes.size() * sizeof(gpu::BvhNode) + leaves.size() * sizeof(gpu::BvhLeaf) +
           triangles.size() * sizeof(gpu::TriangleRecord);
  }
};

// How interior nodes are numbered (--bvh-layout). Only the numbering changes: every node keeps
// its left and right child, so a traversal visits the same nodes and answers the same.
enum class NodeLayout {
  kDfs,            // depth-first, left subtree first
  kDfsLargeFirst,  // depth-first, the child with the larger surface area (more likely hit)
                   // first: it follows its parent in memory
};
const char* node_layout_name(NodeLayout l);
// Name → value, for the command line (CLI11's CheckedTransformer).
const std::map<std::string, NodeLayout>& node_layout_names();

// Interior nodes numbered depth-first (which subtree first: `layout`), leaves in the order met,
// triangle records in leaf order: the same tree always gets the same layout. A tree that is one
// leaf gets an interior root whose right child is an empty leaf. Throws hrpp::Error when the tree
// is deeper than HRPP_STACK_SIZE.
GpuBvh make_gpu_layout(const Bvh& bvh, const Scene& scene, NodeLayout layout = NodeLayout::kDfs);

}  // namespace hrpp
