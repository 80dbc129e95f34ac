// The base BVH: a binary tree over triangle ids, plain data. The builder makes it; the GPU
// layout (gpu_layout.h) and the statistics are derived from it.
#pragma once

#include <cstdint>
#include <vector>

#include "bvh/aabb.h"
#include "common/name_table.h"

namespace hrpp {

// How the builder may split a node: object splits only (binned SAH) or also spatial splits that
// clip triangles at a plane and put the parts on both sides (SBVH, bvh/sbvh_builder.h).
enum class BvhSplits { kObject, kSpatial };  // --bvh-splits
inline constexpr NameTable<BvhSplits, 2> kBvhSplitsNames = {
    {{BvhSplits::kObject, "object"}, {BvhSplits::kSpatial, "spatial"}}};

struct BvhConfig {
  int bin_count = 16;         // SAH bins per axis
  int max_leaf_size = 4;      // no leaf holds more triangles (unless they cannot be separated)
  float traversal_cost = 1.0f;     // SAH cost of one interior node visit
  float intersection_cost = 1.0f;  // SAH cost of one triangle test
  int threads = 0;            // 0: all hardware threads
  BvhSplits splits = BvhSplits::kObject;
  // Spatial splits only: tried at a node when its object split's children overlap by more than
  // spatial_alpha × the root's surface area (Stich et al.'s alpha); at most duplicate_budget ×
  // triangles references more than triangles; unsplit: reference unsplitting.
  float spatial_alpha = 1e-5f;
  float duplicate_budget = 0.3f;
  bool unsplit = true;
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
  // Triangle ids in leaf order (no degenerate ones). With spatial splits an id may be in more
  // than one leaf.
  std::vector<std::uint32_t> prim_ids;
  std::uint32_t degenerate_count = 0;    // triangles left out of the tree (zero area)
  double build_ms = 0.0;
};

}  // namespace hrpp
