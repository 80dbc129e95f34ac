// How both builders (binned_sah_builder.cpp, sbvh_builder.cpp) share a build between threads:
// the top of the tree, the nodes over subtree_threshold() references, is split by all threads
// together; each smaller node becomes a subtree that one thread builds alone into its own array,
// numbered locally (its root first, then children pairs from index 1, as a sequential build
// numbers them), and copy_subtree() moves it into the whole tree's array. The threshold only
// changes who does the work, not the tree.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

#include "bvh/bvh.h"

namespace hrpp::bvh_build {

// With T threads, nodes over max(kMinSubtree, N / (kSubtreesPerThread T)) of the N references
// are split by all threads together; smaller ones become subtrees, handed out largest first. One
// thread: the whole tree is one subtree.
constexpr std::size_t kMinSubtree = std::size_t{1} << 12;
constexpr std::size_t kSubtreesPerThread = 8;

inline std::size_t subtree_threshold(std::size_t refs, int threads) {
  if (threads <= 1) return std::numeric_limits<std::size_t>::max();
  return std::max(kMinSubtree, refs / (kSubtreesPerThread * static_cast<std::size_t>(threads)));
}

// Copies a subtree's nodes, numbered locally, into the whole tree: its root to nodes[root], its
// i-th node (i >= 1) to nodes[base + i - 1]; child links move by base - 1, leaf ranges by
// leaf_base.
inline void copy_subtree(std::span<const Bvh::Node> local, std::uint32_t root, std::uint32_t base,
                         std::uint32_t leaf_base, std::span<Bvh::Node> nodes) {
  for (std::size_t i = 0; i < local.size(); ++i) {
    Bvh::Node n = local[i];
    if (n.is_leaf())
      n.first += leaf_base;
    else if (local.size() > 1)  // not a lone root without references (count 0, first kept)
      n.first += base - 1;
    nodes[i == 0 ? root : base + i - 1] = n;
  }
}

}  // namespace hrpp::bvh_build
