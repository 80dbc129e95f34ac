// The BVH as the GPU (and the CPU reference traversal) reads it: Aila–Laine 64-byte nodes, leaf
// records and triangle records, as plain arrays ready to upload (shaders/shared/gpu_types.h).
#pragma once

#include <cstddef>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "bvh/aabb.h"
#include "bvh/bvh.h"
#include "common/name_table.h"
#include "gpu_types.h"
#include "scene/scene.h"

// Deepest traversal stack the kernels and the CPU reference keep (one entry per tree level).
#define HRPP_STACK_SIZE 64

namespace hrpp {

static_assert(sizeof(gpu::BvhNode) == 64);
static_assert(offsetof(gpu::BvhNode, right_xy) == 16 && offsetof(gpu::BvhNode, lr_z) == 32 &&
              offsetof(gpu::BvhNode, link) == 48);
static_assert(sizeof(gpu::WideNode) == 64 && offsetof(gpu::WideNode, child) == 16 &&
              offsetof(gpu::WideNode, lo) == 32 && offsetof(gpu::WideNode, hi) == 48);
static_assert(sizeof(gpu::WideFloatNode) == 112 && offsetof(gpu::WideFloatNode, child) == 96);
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

// Which interior nodes the trace kernels read (--bvh-nodes).
enum class NodeFormat {
  kBinary,  // the Aila–Laine 64-byte BvhNode: the reference format, and HRPP's
  kWide4,       // 4-wide WideNodes, child boxes quantised (bvh/wide_nodes.h); HRPP off only
  kWide4Float,  // 4-wide WideFloatNodes, child boxes as floats; HRPP off only
};
inline constexpr NameTable<NodeFormat, 3> kNodeFormatNames = {
    {{NodeFormat::kBinary, "binary"},
     {NodeFormat::kWide4, "wide4"},
     {NodeFormat::kWide4Float, "wide4-float"}}};
constexpr const char* node_format_name(NodeFormat f) { return name_in(kNodeFormatNames, f); }

struct GpuBvh {
  std::vector<gpu::BvhNode> nodes;            // nodes[0] is the root, always interior
  std::vector<gpu::BvhLeaf> leaves;
  std::vector<gpu::TriangleRecord> triangles;  // in leaf order
  // The 4-wide formats: the nodes the trace kernels read instead of `nodes` (which the CPU
  // reference and HRPP keep using), over the same leaves and triangles. At most one is filled;
  // neither: NodeFormat::kBinary.
  std::vector<gpu::WideNode> wide_nodes;             // kWide4
  std::vector<gpu::WideFloatNode> wide_float_nodes;  // kWide4Float
  Aabb bounds;                                       // of the whole scene's tree
  NodeFormat format() const {
    if (!wide_nodes.empty()) return NodeFormat::kWide4;
    return wide_float_nodes.empty() ? NodeFormat::kBinary : NodeFormat::kWide4Float;
  }
  // The node array the trace kernels read, as bytes to upload.
  std::span<const std::byte> traced_nodes() const;
  std::size_t bytes() const {
    return nodes.size() * sizeof(gpu::BvhNode) + wide_nodes.size() * sizeof(gpu::WideNode) +
           wide_float_nodes.size() * sizeof(gpu::WideFloatNode) +
           leaves.size() * sizeof(gpu::BvhLeaf) + triangles.size() * sizeof(gpu::TriangleRecord);
  }
};

// How interior nodes are numbered (--bvh-layout). Only the numbering changes: every node keeps
// its left and right child, so a traversal visits the same nodes and answers the same.
enum class NodeLayout {
  kDfs,            // depth-first, left subtree first
  kDfsLargeFirst,  // depth-first, the child with the larger surface area (more likely hit)
                   // first: it follows its parent in memory
};
inline constexpr NameTable<NodeLayout, 2> kNodeLayoutNames = {
    {{NodeLayout::kDfs, "dfs"}, {NodeLayout::kDfsLargeFirst, "dfs-large-first"}}};
constexpr const char* node_layout_name(NodeLayout l) { return name_in(kNodeLayoutNames, l); }

// Interior nodes numbered depth-first (which subtree first: `layout`), leaves in the order met,
// triangle records in leaf order: the same tree always gets the same layout. A tree that is one
// leaf gets an interior root whose right child is an empty leaf. Throws hrpp::Error when the tree
// is deeper than HRPP_STACK_SIZE. A 4-wide `format` adds its wide nodes (bvh/wide_nodes.h;
// kWide4 may throw too).
GpuBvh make_gpu_layout(const Bvh& bvh, const Scene& scene, NodeLayout layout = NodeLayout::kDfs,
                       NodeFormat format = NodeFormat::kBinary);
// The same, consuming `bvh`: its arrays are freed as soon as the layout no longer needs them.
GpuBvh make_gpu_layout(Bvh&& bvh, const Scene& scene, NodeLayout layout = NodeLayout::kDfs,
                       NodeFormat format = NodeFormat::kBinary);

}  // namespace hrpp
