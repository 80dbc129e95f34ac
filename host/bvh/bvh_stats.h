// What `hrpp scene` and the build benchmark report about a BVH.
#pragma once

#include <cstdint>

#include "bvh/bvh.h"

namespace hrpp {

struct BvhStats {
  std::uint32_t triangles = 0;        // in the tree (each counted once)
  std::uint32_t references = 0;       // triangle ids in leaves (spatial splits: some repeat)
  std::uint32_t degenerate = 0;       // left out (ids kept)
  std::uint32_t interior_nodes = 0;
  std::uint32_t leaves = 0;
  std::uint32_t max_depth = 0;        // deepest leaf, root = 0
  double mean_leaf_depth = 0.0;
  double mean_leaf_size = 0.0;        // references per leaf
  std::uint32_t max_leaf_size = 0;
  // SAH cost with the builder's constants: (Ct Σ_interior A(n) + Ci Σ_leaf |l| A(l)) / A(root).
  double sah_cost = 0.0;
  double build_ms = 0.0;
};

BvhStats compute_bvh_stats(const Bvh& bvh, const BvhConfig& config = {});

}  // namespace hrpp
