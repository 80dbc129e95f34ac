// The base BVH: a binary tree over triangle ids, plain data. The builder makes it; the GPU
// layout (gpu_layout.h) and the statistics are derived from it.
#pragma once

#include <cstdint>
#include <vector>

#include "bvh/aabb.h"

namespace hrpp {

struct BvhConfig {
  int bin_count = 16;         // SAH bins per axis
  int max_leaf_size = 4;      // no leaf holds more triangles (unless they cannot be separated)
  float traversal_cost = 1.0f;     // SAH cost of one interior node visit
  float intersection_cost = 1.0f;  // SAH cost of one triangle test
  int threads = 0;            // 0: all hardware threads
};

struct Bvh {
  // count > 0: leaf over prim_ids[first, first + count).
  // count == 0: interior node whose children are nodes[first] and nodes[first + 1].
  struct Node {
    Aabb bounds;
    std::uint32_t first = 0;
    std::uint32_t count = 0;
    bool is_leaf() const { return count > 0; }
  };

  std::vector<Node> nodes;               // nodes[0] is the root
  std::vector<std::uint32_t> prim_ids;   // triangle ids in leaf order (no degenerate ones)
  std::uint32_t degenerate_count = 0;    // triangles left out of the tree (zero area)
  double build_ms = 0.0;
};

}  // namespace hrpp
